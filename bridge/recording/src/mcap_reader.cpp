#include "retreat/recording/mcap_reader.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "crc32.hpp"
#include "retreat/core/paths.hpp"

namespace retreat::recording {
namespace {

constexpr unsigned char magic[] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

const char* record_name(std::uint8_t op) {
  switch (op) {
    case 0x01: return "Header";
    case 0x02: return "Footer";
    case 0x03: return "Schema";
    case 0x04: return "Channel";
    case 0x05: return "Message";
    case 0x06: return "Chunk";
    case 0x07: return "Message Index";
    case 0x08: return "Chunk Index";
    case 0x09: return "Attachment";
    case 0x0A: return "Attachment Index";
    case 0x0B: return "Statistics";
    case 0x0C: return "Metadata";
    case 0x0D: return "Metadata Index";
    case 0x0E: return "Summary Offset";
    case 0x0F: return "Data End";
    default: return "unknown";
  }
}


/// The fields of one record's content, little endian, each checked against the content's end.
/// @p base is the content's offset in the file (or in the chunk), for the error.
class Fields {
 public:
  Fields(std::span<const std::byte> content, std::uint64_t base, const char* where)
      : content_(content), base_(base), where_(where) {}

  std::uint8_t u8() { return static_cast<std::uint8_t>(le(1, "an 8-bit field")); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(le(2, "a 16-bit field")); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(le(4, "a 32-bit field")); }
  std::uint64_t u64() { return le(8, "a 64-bit field"); }
  std::span<const std::byte> bytes(std::uint64_t n, const char* what) {
    need(n, what);
    const auto out = content_.subspan(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return out;
  }
  std::string string() {
    const auto b = bytes(u32(), "a string");
    return {reinterpret_cast<const char*>(b.data()), b.size()};
  }
  std::map<std::string, std::string> string_map() {
    Fields entries(bytes(u32(), "a map"), base_ + at_, where_);
    std::map<std::string, std::string> m;
    while (!entries.done()) {
      auto key = entries.string();
      m[std::move(key)] = entries.string();
    }
    return m;
  }
  std::span<const std::byte> rest() { return bytes(content_.size() - at_, "the rest"); }
  bool done() const { return at_ == content_.size(); }
  std::uint64_t offset() const { return base_ + at_; }

 private:
  void need(std::uint64_t n, const char* what) const {
    if (n > content_.size() - at_) {
      throw McapError(std::string(where_) + " record at byte " + std::to_string(base_) + ": " +
                      what + " of " + std::to_string(n) + " bytes runs past the record's end");
    }
  }
  std::uint64_t le(int n, const char* what) {
    need(static_cast<std::uint64_t>(n), what);
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::to_integer<std::uint64_t>(content_[at_ + i]) << (8 * i);
    at_ += static_cast<std::size_t>(n);
    return v;
  }
  std::span<const std::byte> content_;
  std::uint64_t base_;
  const char* where_;
  std::size_t at_ = 0;
};

class Reader {
 public:
  Reader(std::span<const std::byte> bytes, const McapMessageHandler& on_message)
      : bytes_(bytes), on_message_(on_message) {}

  McapContents read() {
    if (bytes_.size() < sizeof magic || std::memcmp(bytes_.data(), magic, sizeof magic) != 0) {
      throw McapError("not an MCAP file: it does not begin with the MCAP magic bytes");
    }
    std::uint64_t at = sizeof magic;
    bool header = false;
    while (true) {
      if (at == bytes_.size()) {
        throw McapError("truncated at byte " + std::to_string(at) + ": the file ends before its footer");
      }
      if (bytes_.size() - at < 9) {
        throw McapError("truncated at byte " + std::to_string(at) + ": " +
                        std::to_string(bytes_.size() - at) + " bytes left, a record takes at least 9");
      }
      const auto op = std::to_integer<std::uint8_t>(bytes_[at]);
      std::uint64_t length = 0;
      for (int i = 0; i < 8; ++i) length |= std::to_integer<std::uint64_t>(bytes_[at + 1 + i]) << (8 * i);
      const std::uint64_t content_at = at + 9;
      if (length > bytes_.size() - content_at) {
        throw McapError("truncated at byte " + std::to_string(at) + ": a " + record_name(op) + " record of " +
                        std::to_string(length) + " bytes, " + std::to_string(bytes_.size() - content_at) +
                        " left");
      }
      if (!header && op != 0x01) {
        throw McapError("byte " + std::to_string(at) + ": the first record is a " + record_name(op) +
                        " record, not the Header");
      }
      const auto content = bytes_.subspan(static_cast<std::size_t>(content_at), static_cast<std::size_t>(length));
      Fields f(content, content_at, record_name(op));
      if (op == 0x02) {
        footer(f, at);
        if (bytes_.size() - (content_at + length) != sizeof magic ||
            std::memcmp(bytes_.data() + content_at + length, magic, sizeof magic) != 0) {
          throw McapError("byte " + std::to_string(content_at + length) +
                          ": the footer is not followed by the closing magic bytes and the end of the file");
        }
        out_.complete = true;
        return std::move(out_);
      }
      if (op == 0x01) {
        if (header) throw McapError("byte " + std::to_string(at) + ": a second Header record");
        header = true;
        out_.profile = f.string();
        out_.library = f.string();
      } else if (op == 0x0F) {
        const auto crc = f.u32();
        if (crc != 0 && crc != crc32_of(0, bytes_.first(static_cast<std::size_t>(at)))) {
          throw McapError("byte " + std::to_string(at) + ": the data section's CRC does not match its bytes");
        }
      } else if (op == 0x06) {
        chunk(f);
      } else if (op == 0x0C) {
        auto name = f.string();
        out_.metadata.emplace_back(std::move(name), f.string_map());
      } else {
        in_data(op, f);  // schema, channel, message; the summary's records are skipped
      }
      at = content_at + length;
    }
  }

 private:
  /// A record that may appear in the data section or in a chunk.
  void in_data(std::uint8_t op, Fields& f) {
    if (op == 0x03) {
      McapSchema s;
      s.id = f.u16();
      s.name = f.string();
      s.encoding = f.string();
      const auto data = f.bytes(f.u32(), "the schema data");
      s.data.assign(reinterpret_cast<const char*>(data.data()), data.size());
      if (s.id == 0) throw McapError("Schema record at byte " + std::to_string(f.offset()) + ": id 0 is reserved");
      define(out_.schemas, s.id, std::move(s), "schema", f.offset());
    } else if (op == 0x04) {
      McapChannel c;
      c.id = f.u16();
      c.schema_id = f.u16();
      c.topic = f.string();
      c.message_encoding = f.string();
      c.metadata = f.string_map();
      if (c.schema_id != 0 && out_.schemas.count(c.schema_id) == 0) {
        throw McapError("Channel record at byte " + std::to_string(f.offset()) + ": channel '" + c.topic +
                        "' names schema " + std::to_string(c.schema_id) + ", which no Schema record defined");
      }
      define(out_.channels, c.id, std::move(c), "channel", f.offset());
    } else if (op == 0x05) {
      McapMessage m;
      m.channel_id = f.u16();
      m.sequence = f.u32();
      m.log_time = f.u64();
      m.publish_time = f.u64();
      m.data = f.rest();
      const auto channel = out_.channels.find(m.channel_id);
      if (channel == out_.channels.end()) {
        throw McapError("Message record at byte " + std::to_string(f.offset()) + ": channel " +
                        std::to_string(m.channel_id) + ", which no Channel record defined");
      }
      ++out_.messages;
      on_message_(channel->second, m);
    }
    // Every other record (indexes, statistics, attachments, summary offsets, unknown opcodes) is
    // for seeking or for other readers: skipped, as the specification lets a reader do.
  }

  /// A schema or channel: defined once; the summary section repeats it identically.
  template <class Map, class Value>
  static void define(Map& map, std::uint16_t id, Value&& value, const char* what, std::uint64_t offset) {
    const auto [it, added] = map.try_emplace(id, std::forward<Value>(value));
    if (added) return;
    const auto& old = it->second;
    bool same = false;
    if constexpr (std::is_same_v<std::decay_t<Value>, McapSchema>) {
      same = old.name == value.name && old.encoding == value.encoding && old.data == value.data;
    } else {
      same = old.schema_id == value.schema_id && old.topic == value.topic &&
             old.message_encoding == value.message_encoding && old.metadata == value.metadata;
    }
    if (!same) {
      throw McapError("byte " + std::to_string(offset) + ": " + what + " " + std::to_string(id) +
                      " is defined twice, differently");
    }
  }

  void chunk(Fields& f) {
    const std::uint64_t start = f.offset();
    f.u64();  // message start time
    f.u64();  // message end time
    const auto size = f.u64();
    const auto crc = f.u32();
    const auto compression = f.string();
    const auto records = f.bytes(f.u64(), "the chunk's records");
    if (size > mcap_max_chunk_size) {
      throw McapError("Chunk record at byte " + std::to_string(start) + ": " + std::to_string(size) +
                      " bytes uncompressed, more than this reader's limit of " +
                      std::to_string(mcap_max_chunk_size));
    }
    std::span<const std::byte> plain;
    if (compression.empty()) {
      if (records.size() != size) {
        throw McapError("Chunk record at byte " + std::to_string(start) + ": " + std::to_string(records.size()) +
                        " bytes of records, its header says " + std::to_string(size));
      }
      plain = records;
    } else if (compression == "zstd") {
      buffer_.resize(static_cast<std::size_t>(size));
      const std::size_t n = ZSTD_decompress(buffer_.data(), buffer_.size(), records.data(), records.size());
      if (ZSTD_isError(n) || n != size) {
        throw McapError("Chunk record at byte " + std::to_string(start) + ": its zstd data does not decompress to " +
                        std::to_string(size) + " bytes" +
                        (ZSTD_isError(n) ? std::string(" (") + ZSTD_getErrorName(n) + ")" : std::string()));
      }
      plain = buffer_;
    } else {
      throw McapError("Chunk record at byte " + std::to_string(start) + ": compression '" + compression +
                      "', this reader reads 'zstd' and none");
    }
    if (crc != 0 && crc != crc32_of(0, plain)) {
      throw McapError("Chunk record at byte " + std::to_string(start) +
                      ": its records' CRC does not match (a corrupted chunk)");
    }
    // The records inside: the same framing (a chunk holds no chunk, so buffer_ stays as it is).
    const auto own = plain;
    std::uint64_t at = 0;
    while (at < own.size()) {
      if (own.size() - at < 9) {
        throw McapError("Chunk record at byte " + std::to_string(start) + ": a record inside it is cut short");
      }
      const auto op = std::to_integer<std::uint8_t>(own[at]);
      std::uint64_t length = 0;
      for (int i = 0; i < 8; ++i) length |= std::to_integer<std::uint64_t>(own[at + 1 + i]) << (8 * i);
      if (length > own.size() - at - 9) {
        throw McapError("Chunk record at byte " + std::to_string(start) + ": a " + record_name(op) +
                        " record inside it runs past the chunk's end");
      }
      Fields inner(own.subspan(static_cast<std::size_t>(at + 9), static_cast<std::size_t>(length)), start,
                   record_name(op));
      in_data(op, inner);
      at += 9 + length;
    }
  }

  void footer(Fields& f, std::uint64_t at) {
    const auto summary_start = f.u64();
    f.u64();  // summary offset start
    const std::uint64_t crc_end = f.offset();
    const auto crc = f.u32();
    if (summary_start > at) {
      throw McapError("Footer record at byte " + std::to_string(at) + ": the summary starts at byte " +
                      std::to_string(summary_start) + ", after the footer");
    }
    if (crc != 0) {
      const std::uint64_t from = summary_start != 0 ? summary_start : at;
      if (crc != crc32_of(0, bytes_.subspan(static_cast<std::size_t>(from), static_cast<std::size_t>(crc_end - from)))) {
        throw McapError("Footer record at byte " + std::to_string(at) +
                        ": the summary section's CRC does not match its bytes");
      }
    }
  }

  std::span<const std::byte> bytes_;
  const McapMessageHandler& on_message_;
  McapContents out_;
  std::vector<std::byte> buffer_;
};

}  // namespace

McapContents read_mcap(std::span<const std::byte> bytes, const McapMessageHandler& on_message) {
  return Reader(bytes, on_message).read();
}

McapContents read_mcap_file(const std::string& path, const McapMessageHandler& on_message) {
  const auto bytes = retreat::read_file(path);
  if (!bytes) throw McapError("'" + path + "': cannot read it as a file");
  try {
    return read_mcap(std::as_bytes(std::span(bytes->data(), bytes->size())), on_message);
  } catch (const McapError& e) {
    throw McapError("'" + path + "': " + e.what());
  }
}

}  // namespace retreat::recording
