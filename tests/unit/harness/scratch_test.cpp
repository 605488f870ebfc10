// The suite's main() (tests/support/src/test_main.cpp): every test process writes in a scratch
// directory of its own, removed when its tests pass and kept, with its path printed, when one
// fails. scratch_probe.cpp is run as a child process with TMPDIR pointing at an empty directory.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "retreat/testing/process.hpp"

namespace {

namespace fs = std::filesystem;
using retreat::testing::ChildProcess;
using retreat::testing::hang_ceiling;
using retreat::testing::read_file;

struct ProbeRun {
  int exit_code;
  std::string output;
  std::vector<fs::path> left;  ///< what the probe left in its TMPDIR
};

ProbeRun run_probe(const std::string& test) {
  const fs::path outer = fs::path(::testing::TempDir()) / ("outer_" + test);
  fs::remove_all(outer);
  fs::create_directories(outer);
  const std::string log = ::testing::TempDir() + "/probe_" + test + ".log";
  ChildProcess probe({RETREAT_SCRATCH_PROBE, "--gtest_filter=ScratchProbe." + test}, log,
                     {"TMPDIR=" + outer.string()});
  const auto code = probe.wait_for(hang_ceiling);
  ProbeRun run{code.value_or(-1), read_file(log), {}};
  for (const auto& entry : fs::recursive_directory_iterator(outer))
    run.left.push_back(entry.path());
  return run;
}

TEST(TestScratch, APassingTestProcessLeavesNothingBehind) {
  const auto run = run_probe("Passes");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(run.left.empty()) << run.left.size() << " files left, the first " << run.left.front();
}

TEST(TestScratch, AFailingTestProcessKeepsItsFilesAndSaysWhere) {
  const auto run = run_probe("Fails");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  // One scratch directory holding the test's own file and its child process's.
  ASSERT_EQ(run.left.size(), 3u) << run.output;
  const auto directory = std::find_if(run.left.begin(), run.left.end(),
                                      [](const fs::path& p) { return fs::is_directory(p); });
  ASSERT_NE(directory, run.left.end());
  const fs::path scratch = *directory;
  EXPECT_EQ(scratch.filename().string().rfind("retreat-test.", 0), 0u) << scratch;
  EXPECT_TRUE(fs::exists(scratch / "own.txt"));
  EXPECT_TRUE(fs::exists(scratch / "child.txt"));
  EXPECT_NE(run.output.find("kept in " + scratch.string()), std::string::npos) << run.output;
}

}  // namespace
