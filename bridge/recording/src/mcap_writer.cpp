#include "retreat/recording/mcap_writer.hpp"

#include <zstd.h>

#include <cstring>
#include <stdexcept>

#include "crc32.hpp"

namespace retreat::recording {
namespace {

// Record opcodes (MCAP spec, "Records").
enum Opcode : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  statistics = 0x0B,
  metadata = 0x0C,
  metadata_index = 0x0D,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

constexpr std::byte magic[] = {std::byte{0x89}, std::byte{'M'}, std::byte{'C'},  std::byte{'A'},
                               std::byte{'P'},  std::byte{'0'}, std::byte{'\r'}, std::byte{'\n'}};

/// Little-endian fields, as the spec lays them out.
class Fields {
 public:
  Fields& u8(std::uint8_t v) { return le(v, 1); }
  Fields& u16(std::uint16_t v) { return le(v, 2); }
  Fields& u32(std::uint32_t v) { return le(v, 4); }
  Fields& u64(std::uint64_t v) { return le(v, 8); }
  Fields& bytes(std::span<const std::byte> b) {
    out_.insert(out_.end(), b.begin(), b.end());
    return *this;
  }
  Fields& string(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    return bytes(std::as_bytes(std::span(s.data(), s.size())));
  }
  Fields& string_map(const std::map<std::string, std::string>& m) {
    Fields entries;
    for (const auto& [k, v] : m) entries.string(k).string(v);
    u32(static_cast<std::uint32_t>(entries.out_.size()));
    return bytes(entries.out_);
  }
  std::vector<std::byte>& out() { return out_; }

 private:
  Fields& le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<std::byte>((v >> (8 * i)) & 0xFF));
    return *this;
  }
  std::vector<std::byte> out_;
};

/// opcode, u64 length, content.
std::vector<std::byte> record(Opcode op, Fields& content) {
  Fields r;
  r.u8(op).u64(content.out().size()).bytes(content.out());
  return std::move(r.out());
}

}  // namespace

McapWriter::McapWriter(const std::string& path, McapOptions options)
    : file_(std::fopen(path.c_str(), "wb")), path_(path), options_(std::move(options)) {
  if (file_ == nullptr) throw std::runtime_error("cannot write '" + path + "'");
  put(std::vector<std::byte>(std::begin(magic), std::end(magic)));
  Fields h;
  h.string(options_.profile).string(options_.library);
  put(record(header, h));
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; close() reports
  }
}

void McapWriter::put(const std::vector<std::byte>& bytes) {
  if (file_ == nullptr) throw std::runtime_error("'" + path_ + "': already closed");
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    throw std::runtime_error("cannot write '" + path_ + "'");
  }
  offset_ += bytes.size();
  data_crc_ = crc32_of(data_crc_, bytes);
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding,
                                     const std::string& data) {
  if (schemas_.size() >= 0xFFFF)
    throw std::length_error("MCAP schema '" + name + "': at most 65,535 schemas");
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);  // 0 means "no schema"
  Fields f;
  f.u16(id).string(name).string(encoding).u32(static_cast<std::uint32_t>(data.size()));
  f.bytes(std::as_bytes(std::span(data.data(), data.size())));
  schemas_.push_back(record(schema, f));
  put(schemas_.back());
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  if (schema_id > schemas_.size()) {
    throw std::invalid_argument("MCAP channel '" + topic + "': schema " +
                                std::to_string(schema_id) + " was not added");
  }
  if (channels_.size() >= 0xFFFF)
    throw std::length_error("MCAP channel '" + topic + "': at most 65,535 channels");
  const auto id = static_cast<std::uint16_t>(channels_.size());
  Fields f;
  f.u16(id).u16(schema_id).string(topic).string(message_encoding).string_map(metadata);
  channels_.push_back(record(channel, f));
  channel_schema_.push_back(schema_id);
  put(channels_.back());
  return id;
}

void McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time,
                       std::uint64_t publish_time, std::span<const std::byte> data) {
  if (channel_id >= channels_.size()) {
    throw std::invalid_argument("MCAP message: channel " + std::to_string(channel_id) +
                                " was not added");
  }
  if (closed_) throw std::logic_error("'" + path_ + "': a message after close()");
  if (chunk_.empty()) {
    chunk_start_ = chunk_end_ = log_time;
  }
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
  Fields f;
  f.u16(channel_id).u32(sequence).u64(log_time).u64(publish_time).bytes(data);
  const auto r = record(message, f);
  chunk_.insert(chunk_.end(), r.begin(), r.end());
  first_time_ = message_count_ == 0 ? log_time : std::min(first_time_, log_time);
  last_time_ = message_count_ == 0 ? log_time : std::max(last_time_, log_time);
  ++message_count_;
  ++channel_counts_[channel_id];
  if (chunk_.size() >= options_.chunk_size) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  std::vector<std::byte> packed;
  std::string compression;
  if (options_.compression == Compression::zstd) {
    compression = "zstd";
    packed.resize(ZSTD_compressBound(chunk_.size()));
    const std::size_t n =
        ZSTD_compress(packed.data(), packed.size(), chunk_.data(), chunk_.size(), 1);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
    packed.resize(n);
  } else {
    packed = chunk_;
  }
  ChunkIndex index;
  index.start_time = chunk_start_;
  index.end_time = chunk_end_;
  index.offset = offset_;
  index.compressed_size = packed.size();
  index.uncompressed_size = chunk_.size();
  Fields c;
  c.u64(chunk_start_)
      .u64(chunk_end_)
      .u64(chunk_.size())
      .u32(crc32_of(0, chunk_))
      .string(compression);
  c.u64(packed.size()).bytes(packed);
  put(record(chunk, c));
  index.length = offset_ - index.offset;
  const std::uint64_t indexes_start = offset_;
  for (const auto& [channel_id, entries] : chunk_index_) {
    index.message_index_offsets[channel_id] = offset_;
    Fields m;
    Fields pairs;
    for (const auto& [time, at] : entries) pairs.u64(time).u64(at);
    m.u16(channel_id).u32(static_cast<std::uint32_t>(pairs.out().size())).bytes(pairs.out());
    put(record(message_index, m));
  }
  index.message_index_length = offset_ - indexes_start;
  chunks_.push_back(std::move(index));
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::add_metadata(const std::string& name,
                              const std::map<std::string, std::string>& meta) {
  Fields f;
  f.string(name).string_map(meta);
  const auto r = record(metadata, f);
  metadata_.push_back({offset_, r.size(), name});
  put(r);
}

void McapWriter::close() {
  if (closed_ || file_ == nullptr) return;
  closed_ = true;
  flush_chunk();
  {
    Fields end;
    end.u32(data_crc_);
    put(record(data_end, end));
  }
  // The summary: one group per record kind, each located by a Summary Offset record.
  const std::uint64_t summary_start = offset_;
  data_crc_ = 0;  // from here on: the summary's CRC
  std::vector<std::tuple<Opcode, std::uint64_t, std::uint64_t>> groups;
  const auto group = [&](Opcode op, const auto& write_records) {
    const std::uint64_t start = offset_;
    write_records();
    if (offset_ > start) groups.emplace_back(op, start, offset_ - start);
  };
  group(schema, [&] {
    for (const auto& r : schemas_) put(r);
  });
  group(channel, [&] {
    for (const auto& r : channels_) put(r);
  });
  group(statistics, [&] {
    Fields s;
    Fields counts;
    for (const auto& [id, n] : channel_counts_) counts.u16(id).u64(n);
    s.u64(message_count_)
        .u16(static_cast<std::uint16_t>(schemas_.size()))
        .u32(static_cast<std::uint32_t>(channels_.size()))
        .u32(0)  // attachments
        .u32(static_cast<std::uint32_t>(metadata_.size()))
        .u32(static_cast<std::uint32_t>(chunks_.size()))
        .u64(first_time_)
        .u64(last_time_)
        .u32(static_cast<std::uint32_t>(counts.out().size()))
        .bytes(counts.out());
    put(record(statistics, s));
  });
  group(chunk_index, [&] {
    for (const auto& c : chunks_) {
      Fields f;
      Fields offsets;
      for (const auto& [id, at] : c.message_index_offsets) offsets.u16(id).u64(at);
      f.u64(c.start_time)
          .u64(c.end_time)
          .u64(c.offset)
          .u64(c.length)
          .u32(static_cast<std::uint32_t>(offsets.out().size()))
          .bytes(offsets.out())
          .u64(c.message_index_length)
          .string(options_.compression == Compression::zstd ? "zstd" : "")
          .u64(c.compressed_size)
          .u64(c.uncompressed_size);
      put(record(chunk_index, f));
    }
  });
  group(metadata_index, [&] {
    for (const auto& m : metadata_) {
      Fields f;
      f.u64(m.offset).u64(m.length).string(m.name);
      put(record(metadata_index, f));
    }
  });
  const std::uint64_t summary_offset_start = offset_;
  for (const auto& [op, start, length] : groups) {
    Fields f;
    f.u8(op).u64(start).u64(length);
    put(record(summary_offset, f));
  }
  // The footer's CRC covers the summary up to and including its own summary_offset_start.
  Fields foot;
  foot.u8(footer).u64(8 + 8 + 4).u64(summary_start).u64(summary_offset_start);
  const std::uint32_t summary_crc = crc32_of(data_crc_, foot.out());
  foot.u32(summary_crc);
  put(foot.out());
  put(std::vector<std::byte>(std::begin(magic), std::end(magic)));
  const bool ok = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok) throw std::runtime_error("cannot write '" + path_ + "'");
}

}  // namespace retreat::recording
