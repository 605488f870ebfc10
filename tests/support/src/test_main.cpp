// The main() of every GoogleTest executable of the suite (retreat_test in
// deploy/cmake/RetreatHelpers.cmake links it instead of GTest::gtest_main).
//
// Each test process gets a scratch directory of its own, <TMPDIR or /tmp>/retreat-test.XXXXXX,
// and points TMPDIR and TEST_TMPDIR at it before any test runs: ::testing::TempDir(),
// std::filesystem::temp_directory_path() and every child process the test starts (agents, arenas,
// launchers, browsers) then write there. CTest runs one process per test, so two tests, or two
// suites run side by side from two trees, never share a file by its name. When every test of the
// process passes the directory is removed; when one fails it is kept and its path printed, so that
// the logs of a failure in CI can be read.
//
// What stays in /tmp on purpose: /tmp/retreat-domain-<id>.lock (deploy/launch/domain_lock.cpp),
// the flock that keeps two runs on one host off the same DDS domain, must be the same path for
// every process of the host.

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

namespace {

namespace fs = std::filesystem;

std::string env_or_unset(const char* name) {
  const char* value = std::getenv(name);
  return value == nullptr ? "(unset)" : value;
}

/// Creates the scratch directory under the caller's temporary directory and points TMPDIR and
/// TEST_TMPDIR at it; an empty path, and one line on stderr, when it cannot.
fs::path create_scratch_directory() {
  std::error_code error;
  const fs::path parent = fs::temp_directory_path(error);
  if (error) {
    std::cerr << "retreat tests: no temporary directory (TMPDIR=" << env_or_unset("TMPDIR")
              << "): " << error.message() << '\n';
    return {};
  }
  std::string pattern = (parent / "retreat-test.XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    std::cerr << "retreat tests: cannot create a directory like " << pattern << ": "
              << std::strerror(errno) << '\n';
    return {};
  }
  ::setenv("TMPDIR", pattern.c_str(), 1);
  ::setenv("TEST_TMPDIR", pattern.c_str(), 1);
  return pattern;
}

/// Removes the scratch directory when the tests passed; keeps it, and says where, when one failed.
void finish_scratch_directory(const fs::path& directory, bool passed) {
  if (!passed) {
    std::cerr << "retreat tests: the files of the failed test are kept in " << directory.string()
              << '\n';
    return;
  }
  std::error_code error;
  fs::remove_all(directory, error);
  if (error) {
    std::cerr << "retreat tests: could not remove " << directory.string() << ": " << error.message()
              << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const fs::path scratch = create_scratch_directory();
  if (scratch.empty()) return 1;
  const int result = RUN_ALL_TESTS();
  finish_scratch_directory(scratch, result == 0);
  return result;
}
