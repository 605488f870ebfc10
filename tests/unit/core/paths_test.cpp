// retreat/core/paths.hpp: file-system questions and reads that never throw for what a path names.

#include "retreat/core/paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace retreat {
namespace {

namespace fs = std::filesystem;

TEST(ReadRegularFile, GivesAFilesBytesAndNothingForADirectoryOrAMissingPath) {
  const fs::path dir = fs::path(::testing::TempDir()) / "paths_test";
  fs::create_directories(dir);
  const std::string file = (dir / "token").string();
  std::ofstream(file, std::ios::binary) << std::string("abc\0def\n", 8);
  const std::string empty = (dir / "empty").string();
  std::ofstream{empty};

  EXPECT_EQ(read_regular_file(file), std::optional<std::string>(std::string("abc\0def\n", 8)));
  EXPECT_EQ(read_regular_file(empty), std::optional<std::string>(""));
  // A directory opens as an std::ifstream and its first read throws: here, nothing.
  EXPECT_EQ(read_regular_file(dir.string()), std::nullopt);
  EXPECT_EQ(read_regular_file((dir / "missing").string()), std::nullopt);
  EXPECT_EQ(read_regular_file(std::string(5000, 'x')), std::nullopt);  // a name the OS refuses
  EXPECT_EQ(read_regular_file("/dev/null"), std::nullopt);             // not a regular file
}

}  // namespace
}  // namespace retreat
