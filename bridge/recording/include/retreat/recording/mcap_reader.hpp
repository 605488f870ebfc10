#pragma once
/// @file
/// A reader of MCAP files (https://mcap.dev/spec, format version 0): the records of the data
/// section in file order, chunks decompressed (zstd or none) and every CRC the file gives
/// checked. It reads what McapWriter writes and what other writers (rosbag2, the reference
/// libraries) write, as long as its chunks are zstd-compressed or not compressed. Every flaw of
/// a file (not MCAP, truncated, a record that runs past its end, a bad CRC, a message on a
/// channel never defined, an unknown compression) throws McapError with one line naming the
/// byte offset; nothing is read past the end of the bytes (tests/fuzz: fuzz_mcap_reader).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace retreat::recording {

/// A file that is not a readable MCAP file; the message is one line.
class McapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding, data;
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  ///< 0: no schema
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

/// One message; @ref data points into the reader's buffers and is valid during the callback.
struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      ///< [ns]
  std::uint64_t publish_time = 0;  ///< [ns]
  std::span<const std::byte> data;
};

/// What a file holds besides its messages.
struct McapContents {
  std::string profile, library;                     ///< the Header's
  std::map<std::uint16_t, McapSchema> schemas;      ///< by id
  std::map<std::uint16_t, McapChannel> channels;    ///< by id
  std::vector<std::pair<std::string, std::map<std::string, std::string>>> metadata;  ///< in file order
  std::uint64_t messages = 0;  ///< messages read
  bool complete = false;       ///< the footer and the closing magic were read
};

using McapMessageHandler = std::function<void(const McapChannel&, const McapMessage&)>;

/// Largest chunk this reader decompresses [bytes]; a chunk that says it is larger is refused
/// (McapWriter's chunks are about 1 MiB; rosbag2's default is 4 MiB).
inline constexpr std::uint64_t mcap_max_chunk_size = std::uint64_t{256} << 20;

/// Reads @p bytes, an MCAP file, calling @p on_message for every message in file order.
/// @throws McapError (one line: the byte offset and what is wrong with it).
McapContents read_mcap(std::span<const std::byte> bytes, const McapMessageHandler& on_message);

/// The same for the file @p path; the error names the path.
/// @throws McapError, also when the file cannot be read.
McapContents read_mcap_file(const std::string& path, const McapMessageHandler& on_message);

}  // namespace retreat::recording
