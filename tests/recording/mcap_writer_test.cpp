// McapWriter's refusals (the files it writes are checked by the reference reader: read_mcap.mjs).

#include "retreat/recording/mcap_writer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using retreat::recording::McapWriter;

std::string temp_file(const std::string& name) { return ::testing::TempDir() + "/" + name; }

TEST(McapWriter, NamesAPathItCannotWrite) {
  try {
    McapWriter mcap("/nonexistent/dir/run.mcap");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/run.mcap"), std::string::npos)
        << e.what();
  }
}

TEST(McapWriter, RefusesAChannelOfAnUnknownSchemaAndAMessageOfAnUnknownChannel) {
  const auto path = temp_file("refusals.mcap");
  {
    McapWriter mcap(path);
    EXPECT_THROW(mcap.add_channel(1, "/frames", "cdr"), std::invalid_argument);
    const auto schema = mcap.add_schema("S", "omgidl", "struct S { uint32 x; };");
    EXPECT_EQ(schema, 1);
    EXPECT_EQ(mcap.add_channel(schema, "/frames", "cdr"), 0);
    const std::vector<std::byte> data(4);
    EXPECT_THROW(mcap.write(1, 0, 0, 0, data), std::invalid_argument);
    mcap.write(0, 0, 0, 0, data);
    EXPECT_EQ(mcap.message_count(), 1U);
    mcap.close();
    EXPECT_THROW(mcap.write(0, 1, 1, 1, data), std::logic_error);
    mcap.close();  // a second close does nothing
  }
  EXPECT_GT(std::filesystem::file_size(path), 8U * 2);
  std::filesystem::remove(path);
}

TEST(McapWriter, ClosesTheFileWhenDestroyed) {
  const auto path = temp_file("destroyed.mcap");
  std::uintmax_t size = 0;
  {
    McapWriter mcap(path);
    mcap.add_channel(0, "/log", "json");
    const std::string text = "{}";
    mcap.write(0, 0, 5, 5, std::as_bytes(std::span(text.data(), text.size())));
  }
  size = std::filesystem::file_size(path);
  McapWriter closed(temp_file("closed.mcap"));
  closed.add_channel(0, "/log", "json");
  const std::string text = "{}";
  closed.write(0, 0, 5, 5, std::as_bytes(std::span(text.data(), text.size())));
  closed.close();
  EXPECT_EQ(size,
            std::filesystem::file_size(temp_file("closed.mcap")));  // the same summary and footer
  std::filesystem::remove(path);
  std::filesystem::remove(temp_file("closed.mcap"));
}

}  // namespace
