// A GoogleTest executable with the suite's main() (tests/support/src/test_main.cpp), run by
// scratch_test.cpp and never by CTest: one test that passes and one that fails, each leaving a file
// of its own and one of a child process in the temporary directory.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

void leave_files() {
  std::ofstream(::testing::TempDir() + "/own.txt") << "written by the test\n";
  // A child process writes where TMPDIR says, as the agents and arenas a test starts do.
  ASSERT_EQ(std::system("sh -c 'echo written by a child > \"$TMPDIR/child.txt\"'"), 0);
}

TEST(ScratchProbe, Passes) {
  leave_files();
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::temp_directory_path() / "child.txt"));
}

TEST(ScratchProbe, Fails) {
  leave_files();
  ADD_FAILURE() << "this test fails on purpose";
}

}  // namespace
