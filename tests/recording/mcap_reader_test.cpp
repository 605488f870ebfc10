// McapReader against McapWriter's files: every record read back, and every flaw of a file (each
// truncation, a flipped byte in a chunk, in the data section or in the summary, a message on an
// undefined channel) refused with one line, never a crash. (The reader against an independent
// writer, @mcap/core's: Recording.OurReaderReadsTheReferenceWriter.)

#include "retreat/recording/mcap_reader.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "retreat/recording/mcap_writer.hpp"

namespace {

using namespace retreat::recording;

std::string temp_file(const std::string& name) { return ::testing::TempDir() + "/" + name; }

std::vector<std::byte> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> out(chars.size());
  std::memcpy(out.data(), chars.data(), chars.size());
  return out;
}

struct Written {
  std::uint16_t channel;
  std::uint32_t sequence;
  std::uint64_t log_time;
  std::vector<std::byte> data;
};

/// A file of @p n messages on two channels, chunks of @p chunk bytes; returns what was written.
std::vector<Written> write_sample(const std::string& path, Compression compression, std::size_t chunk, int n) {
  McapOptions options;
  options.compression = compression;
  options.chunk_size = chunk;
  McapWriter mcap(path, options);
  const auto schema = mcap.add_schema("test::S", "omgidl", "module test { struct S { uint32 x; }; };");
  const auto a = mcap.add_channel(schema, "/a", "cdr", {{"vendor", "x"}});
  const auto b = mcap.add_channel(0, "/b", "raw");
  mcap.add_metadata("retreat", {{"seed", "3"}});
  std::vector<Written> out;
  for (int i = 0; i < n; ++i) {
    std::vector<std::byte> data(static_cast<std::size_t>(i % 23));
    for (std::size_t j = 0; j < data.size(); ++j) data[j] = static_cast<std::byte>(i * 13 + j);
    const auto channel = i % 2 == 0 ? a : b;
    mcap.write(channel, static_cast<std::uint32_t>(i), 1000 + i, 999 + i, data);
    out.push_back({channel, static_cast<std::uint32_t>(i), static_cast<std::uint64_t>(1000 + i), data});
  }
  mcap.add_metadata("retreat.recorder", {{"messages", std::to_string(n)}});
  mcap.close();
  return out;
}

void expect_reads_back(Compression compression, std::size_t chunk, int n) {
  const auto path = temp_file("reader.mcap");
  const auto written = write_sample(path, compression, chunk, n);
  std::vector<Written> read;
  const auto contents = read_mcap_file(path, [&](const McapChannel& c, const McapMessage& m) {
    read.push_back({c.id, m.sequence, m.log_time, {m.data.begin(), m.data.end()}});
    EXPECT_EQ(m.publish_time + 1, m.log_time);
  });
  EXPECT_TRUE(contents.complete);
  EXPECT_EQ(contents.library, "retreat");
  EXPECT_EQ(contents.messages, static_cast<std::uint64_t>(n));
  ASSERT_EQ(contents.schemas.size(), 1U);
  EXPECT_EQ(contents.schemas.at(1).name, "test::S");
  EXPECT_EQ(contents.schemas.at(1).data, "module test { struct S { uint32 x; }; };");
  ASSERT_EQ(contents.channels.size(), 2U);
  EXPECT_EQ(contents.channels.at(0).topic, "/a");
  EXPECT_EQ(contents.channels.at(0).metadata.at("vendor"), "x");
  EXPECT_EQ(contents.channels.at(1).schema_id, 0);
  ASSERT_EQ(contents.metadata.size(), 2U);
  EXPECT_EQ(contents.metadata[0].first, "retreat");
  EXPECT_EQ(contents.metadata[0].second.at("seed"), "3");
  EXPECT_EQ(contents.metadata[1].second.at("messages"), std::to_string(n));
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].channel, written[i].channel) << i;
    EXPECT_EQ(read[i].sequence, written[i].sequence) << i;
    EXPECT_EQ(read[i].log_time, written[i].log_time) << i;
    EXPECT_EQ(read[i].data, written[i].data) << i;
  }
  std::filesystem::remove(path);
}

TEST(McapReader, ReadsBackEveryRecordMcapWriterWrote) {
  expect_reads_back(Compression::zstd, 256, 2000);   // many zstd chunks
  expect_reads_back(Compression::none, 1 << 20, 300);  // one uncompressed chunk
  expect_reads_back(Compression::zstd, 4096, 0);       // no message
}

/// Reads @p bytes and returns the error's line ("" if it read them).
std::string error_of(const std::vector<std::byte>& bytes) {
  try {
    read_mcap(bytes, [](const McapChannel&, const McapMessage&) {});
  } catch (const McapError& e) {
    return e.what();
  }
  return "";
}

TEST(McapReader, RefusesEveryTruncationInOneLine) {
  const auto path = temp_file("truncated.mcap");
  write_sample(path, Compression::zstd, 128, 40);
  const auto bytes = file_bytes(path);
  std::filesystem::remove(path);
  ASSERT_EQ(error_of(bytes), "");
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::vector<std::byte> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    const auto error = error_of(cut);
    ASSERT_FALSE(error.empty()) << "a file cut to " << n << " of " << bytes.size() << " bytes was read";
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST(McapReader, RefusesACorruptedChunkDataSectionOrSummary) {
  const auto path = temp_file("corrupted.mcap");
  write_sample(path, Compression::none, 1 << 20, 50);
  const auto bytes = file_bytes(path);
  std::filesystem::remove(path);
  // The uncompressed chunk holds the messages' bytes: find message 21's data (21 * 13, ...).
  const std::byte marker[] = {std::byte{21 * 13 & 0xFF}, std::byte{(21 * 13 + 1) & 0xFF}, std::byte{(21 * 13 + 2) & 0xFF}};
  const auto at = std::search(bytes.begin(), bytes.end(), std::begin(marker), std::end(marker));
  ASSERT_NE(at, bytes.end());
  auto chunk = bytes;
  chunk[static_cast<std::size_t>(at - bytes.begin())] ^= std::byte{0x40};
  EXPECT_NE(error_of(chunk).find("CRC does not match"), std::string::npos) << error_of(chunk);

  // The last byte before the closing magic is the footer's summary CRC.
  auto summary = bytes;
  summary[bytes.size() - 9] ^= std::byte{1};
  EXPECT_NE(error_of(summary).find("summary section's CRC"), std::string::npos) << error_of(summary);

  // Trailing garbage after the closing magic.
  auto trailing = bytes;
  trailing.push_back(std::byte{0});
  EXPECT_NE(error_of(trailing).find("closing magic"), std::string::npos) << error_of(trailing);

  // Not MCAP at all.
  EXPECT_NE(error_of({std::byte{'P'}, std::byte{'K'}}).find("not an MCAP file"), std::string::npos);
}

TEST(McapReader, RefusesAMessageOnAChannelNoRecordDefined) {
  // magic, Header, a Message on channel 7, Data End, Footer, magic; no CRCs (0: not checked).
  std::vector<std::byte> f;
  const auto put = [&](std::initializer_list<int> v) {
    for (const int b : v) f.push_back(static_cast<std::byte>(b));
  };
  const auto u64 = [&](std::uint64_t v) {
    for (int i = 0; i < 8; ++i) f.push_back(static_cast<std::byte>(v >> (8 * i)));
  };
  put({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  put({0x01});
  u64(8);
  put({0, 0, 0, 0, 0, 0, 0, 0});  // two empty strings
  put({0x05});
  u64(2 + 4 + 8 + 8 + 1);
  put({7, 0, 0, 0, 0, 0});
  u64(1);
  u64(1);
  put({0xAB});
  put({0x0F});
  u64(4);
  put({0, 0, 0, 0});
  put({0x02});
  u64(20);
  u64(0);
  u64(0);
  put({0, 0, 0, 0});
  put({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  EXPECT_NE(error_of(f).find("channel 7, which no Channel record defined"), std::string::npos) << error_of(f);
}

}  // namespace
