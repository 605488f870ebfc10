// retreat/core/paths.hpp: file-system questions and reads that never throw for what a path names.

#include "retreat/core/paths.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace retreat {
namespace {

namespace fs = std::filesystem;

TEST(ReadFile, GivesAFilesOrAPipesBytesAndNothingForADirectoryADeviceOrAMissingPath) {
  const fs::path dir = fs::path(::testing::TempDir()) / "paths_test";
  fs::create_directories(dir);
  const std::string file = (dir / "token").string();
  std::ofstream(file, std::ios::binary) << std::string("abc\0def\n", 8);
  const std::string empty = (dir / "empty").string();
  std::ofstream{empty};

  EXPECT_EQ(read_file(file), std::optional<std::string>(std::string("abc\0def\n", 8)));
  EXPECT_EQ(read_file(empty), std::optional<std::string>(""));
  // A directory opens as an std::ifstream and its first read throws: here, nothing.
  EXPECT_EQ(read_file(dir.string()), std::nullopt);
  EXPECT_EQ(read_file((dir / "missing").string()), std::nullopt);
  EXPECT_EQ(read_file(std::string(5000, 'x')), std::nullopt);  // a name the OS refuses
  EXPECT_EQ(read_file("/dev/null"), std::nullopt);             // a device

  // A pipe, as `--token-file <(command)` gives one: read to its end.
  const std::string pipe = (dir / "pipe").string();
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(pipe) << "from a pipe\n"; });
  const auto read = read_file(pipe);
  EXPECT_EQ(read, std::optional<std::string>("from a pipe\n"));
  if (!read) {  // not read: the writer still waits for a reader; be that reader, so that it ends
    std::ifstream drain(pipe);
    const std::string rest((std::istreambuf_iterator<char>(drain)), std::istreambuf_iterator<char>());
  }
  writer.join();
}

}  // namespace
}  // namespace retreat
