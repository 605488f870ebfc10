#pragma once
// The CRC-32 of the MCAP specification (IEEE 802.3, reflected), which zlib's crc32 computes;
// shared by the writer and the reader.

#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

namespace retreat::recording {

/// Continues @p crc over @p bytes (start with 0). zlib takes lengths as uInt: fed in parts.
inline std::uint32_t crc32_of(std::uint32_t crc, std::span<const std::byte> bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min<std::size_t>(bytes.size() - done, std::size_t{1} << 30);
    crc = static_cast<std::uint32_t>(
        ::crc32(crc, reinterpret_cast<const Bytef*>(bytes.data() + done), static_cast<uInt>(n)));
    done += n;
  }
  return crc;
}

}  // namespace retreat::recording
