#pragma once
/// @file
/// A writer of MCAP files (https://mcap.dev/spec, format version 0), the recording format of
/// ROS 2's rosbag2 and Foxglove: schemas, channels, messages grouped in zstd-compressed chunks
/// with their message indexes, metadata, and the summary section (statistics, chunk and metadata
/// indexes) that lets a reader seek. Debian packages no MCAP library for C++; this is the
/// documented format written out, checked against the reference TypeScript reader
/// (@mcap/core) by tests/recording.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace retreat::recording {

/// How chunks are compressed.
enum class Compression { none, zstd };

struct McapOptions {
  std::string profile;              ///< the Header's profile ("" for none, "ros2" for rosbag2)
  std::string library = "retreat";  ///< the Header's library
  Compression compression = Compression::zstd;
  std::size_t chunk_size = 1 << 20;  ///< a chunk is closed once its records reach this [bytes]
};

/// Writes one MCAP file, in order: schemas and channels before the messages that use them.
/// Messages are buffered into chunks; close() writes the last chunk, the summary and the
/// footer. Every write throws std::runtime_error if the file cannot be written (the file is
/// then incomplete, but what was written before stays readable by a streaming reader).
class McapWriter {
 public:
  /// Creates (or truncates) @p path and writes the magic and the Header.
  /// @throws std::runtime_error naming the path if it cannot be opened.
  McapWriter(const std::string& path, McapOptions options = {});
  /// Closes the file if close() was not called (errors are then swallowed).
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Adds a schema (e.g. name "retreat::msg::ProximityFrame", encoding "omgidl", the IDL text)
  /// and returns its id (1, 2, ...).
  /// @throws std::length_error beyond 65,535 schemas (the format's 16-bit ids).
  std::uint16_t add_schema(const std::string& name, const std::string& encoding,
                           const std::string& data);

  /// Adds a channel on @p topic whose messages are encoded as @p message_encoding (e.g. "cdr")
  /// with schema @p schema_id (0: no schema) and returns its id (0, 1, ...).
  /// @throws std::invalid_argument if @p schema_id is not 0 and not a schema added before;
  ///         std::length_error beyond 65,535 channels.
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic,
                            const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});

  /// Adds a message on @p channel_id; @p log_time and @p publish_time in nanoseconds.
  /// @throws std::invalid_argument if @p channel_id was not added; std::logic_error after close().
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
             std::uint64_t publish_time, std::span<const std::byte> data);

  /// Adds a Metadata record (e.g. name "retreat", {"scenario": ..., "seed": ...}).
  void add_metadata(const std::string& name, const std::map<std::string, std::string>& metadata);

  /// Writes the last chunk, the Data End record, the summary section, the footer and the closing
  /// magic, and closes the file. Further calls do nothing.
  void close();

  std::uint64_t message_count() const noexcept { return message_count_; }

 private:
  struct ChunkIndex {
    std::uint64_t start_time = 0, end_time = 0, offset = 0, length = 0;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
    std::uint64_t message_index_length = 0, compressed_size = 0, uncompressed_size = 0;
  };
  struct MetadataIndex {
    std::uint64_t offset = 0, length = 0;
    std::string name;
  };

  void put(const std::vector<std::byte>& bytes);  ///< to the file, counted and CRC'd
  void flush_chunk();

  std::FILE* file_ = nullptr;
  std::string path_;
  McapOptions options_;
  std::uint64_t offset_ = 0;                                ///< bytes written so far
  std::uint32_t data_crc_ = 0;                              ///< CRC-32 of everything written so far
  std::vector<std::vector<std::byte>> schemas_, channels_;  ///< their records, for the summary
  std::vector<std::uint16_t> channel_schema_;
  std::vector<std::byte> chunk_;  ///< the open chunk's records, uncompressed
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>>
      chunk_index_;  ///< channel → (log time, offset)
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::vector<ChunkIndex> chunks_;
  std::vector<MetadataIndex> metadata_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0, first_time_ = 0, last_time_ = 0;
  bool closed_ = false;
};

}  // namespace retreat::recording
