// libFuzzer target: the Cyclone DDS 0.10 receive path of one message type
// (docs/fuzzing.md). Cyclone's default serdata checks the 4-byte encapsulation header,
// normalizes the payload against the type's marshalling ops (dds_stream_normalize: bounds,
// byte order, boolean and enum values, sequence lengths) and reads it into a sample
// (dds_stream_read_sample). Both run here through their exported ops-level functions
// (dds_stream_normalize_data, dds_stream_read), then retreat's to_plain and wire::validate.
// Built once per type: RETREAT_FUZZ_TYPE is the IDL struct name, RETREAT_FUZZ_PER_ROBOT is 1
// for types sent on a per-robot topic.

#include <dds/ddsi/ddsi_cdrstream.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <vector>

#include "cyclonedds_convert.hpp"
#include "retreat/wire/validate.hpp"

#define RETREAT_CAT2(a, b) a##b
#define RETREAT_CAT(a, b) RETREAT_CAT2(a, b)

namespace {

namespace cy = retreat::transport::cyclonedds;
using Vendor = RETREAT_CAT(retreat_msg_, RETREAT_FUZZ_TYPE);
const dds_topic_descriptor_t& descriptor =
    RETREAT_CAT(RETREAT_CAT(retreat_msg_, RETREAT_FUZZ_TYPE), _desc);

constexpr std::optional<retreat::wire::RobotId> topic_robot =
    RETREAT_FUZZ_PER_ROBOT ? std::optional<retreat::wire::RobotId>(3) : std::nullopt;

/// XCDR version of an encapsulation identifier (RTPS 2.5 §10.5), 0 if Cyclone would reject it
/// for a @final type.
std::uint32_t xcdr_version(std::uint16_t identifier) {
  switch (identifier) {
    case 0x0000:
    case 0x0001:
      return 1;  // CDR_BE, CDR_LE
    case 0x0006:
    case 0x0007:
      return 2;  // CDR2_BE, CDR2_LE
    default:
      return 0;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4 || size > 0xffff'0000u) return 0;
  const auto identifier = static_cast<std::uint16_t>(data[0] << 8 | data[1]);
  const std::uint32_t version = xcdr_version(identifier);
  if (version == 0) return 0;
  const bool big_endian = (identifier & 1) == 0;
  const bool bswap = big_endian != (DDSRT_ENDIAN == DDSRT_BIG_ENDIAN);

  // Normalization swaps in place: a private, 8-byte aligned copy of the body (as a receive
  // buffer is).
  const auto body_size = static_cast<std::uint32_t>(size - 4);
  std::vector<std::uint64_t> storage(body_size / 8 + 1);
  auto* body = reinterpret_cast<char*>(storage.data());
  std::memcpy(body, data + 4, body_size);
  std::uint32_t offset = 0;
  if (dds_stream_normalize_data(body, &offset, body_size, bswap, version, descriptor.m_ops) ==
      nullptr) {
    return 0;
  }

  Vendor sample;
  std::memset(&sample, 0, sizeof sample);
  dds_istream_t in;
  dds_istream_init(&in, body_size, body, version);
  dds_stream_read(&in, reinterpret_cast<char*>(&sample), descriptor.m_ops);
  dds_istream_fini(&in);
  try {
    (void)retreat::wire::validate(retreat::wire::AnyMessage{cy::to_plain(sample)}, topic_robot);
  } catch (...) {
    // Out of memory while copying a sequence: the adapter counts it as undecodable.
  }
  dds_stream_free_sample(&sample, descriptor.m_ops);
  return 0;
}
