// The launcher's child processes (retreat/launch/child_process.hpp): a program that cannot be
// executed is reported by the constructor or, with ExecCheck::later, by confirm_started(); a
// child inherits no descriptor of the launcher but stdin, stdout and stderr.

#include "retreat/launch/child_process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "retreat/testing/process.hpp"

namespace retreat::launch {
namespace {

namespace fs = std::filesystem;

class ChildProcessTest : public ::testing::Test {
 protected:
  fs::path dir_ = fs::path(::testing::TempDir()) / ("child_process_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string log(const std::string& name) const { return (dir_ / name).string(); }

  /// Waits for the child to end; the ceiling only bounds a failure (these children end at once).
  static ExitStatus wait_for_exit(ChildProcess& child) {
    const auto ceiling = std::chrono::steady_clock::now() + retreat::testing::hang_ceiling;
    while (child.running() && std::chrono::steady_clock::now() < ceiling) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return child.poll().value_or(ExitStatus{-1, 0});
  }
};

TEST_F(ChildProcessTest, AMissingProgramIsReportedByTheConstructor) {
  try {
    ChildProcess child("missing", {(dir_ / "no-such-program").string()}, log("missing.log"));
    FAIL() << "a missing program must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot start " + (dir_ / "no-such-program").string() + ": No such file"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ChildProcessTest, WithTheCheckLaterAMissingProgramIsReportedByConfirmStarted) {
  ChildProcess child("missing", {(dir_ / "no-such-program").string()}, log("missing.log"), {}, ExecCheck::later);
  EXPECT_THROW(child.confirm_started(), std::runtime_error);
  ASSERT_TRUE(child.poll().has_value()) << "the failed child is reaped";
  EXPECT_EQ(child.poll()->code, 127);
  EXPECT_NO_THROW(child.confirm_started()) << "reported once";
}

TEST_F(ChildProcessTest, WithTheCheckLaterAProgramThatRunsIsConfirmedAndEndsWithItsOwnCode) {
  ChildProcess child("sh", {"/bin/sh", "-c", "exit 7"}, log("sh.log"), {}, ExecCheck::later);
  EXPECT_NO_THROW(child.confirm_started());
  EXPECT_EQ(wait_for_exit(child).code, 7);
}

// The launcher's own descriptors (a DDS socket, another child's report pipe: here a file opened
// without close-on-exec) are closed in the child before its program runs.
TEST_F(ChildProcessTest, AChildInheritsOnlyStdinStdoutAndStderr) {
  const int inheritable = ::open("/dev/null", O_RDONLY);  // deliberately without O_CLOEXEC
  ASSERT_GE(inheritable, 3);
  ChildProcess earlier("earlier", {"/bin/sh", "-c", "exit 0"}, log("earlier.log"), {}, ExecCheck::later);
  ChildProcess child("fds", {"/bin/sh", "-c", "ls /proc/$$/fd"}, log("fds.log"));
  EXPECT_EQ(wait_for_exit(child).code, 0);
  earlier.confirm_started();
  wait_for_exit(earlier);
  ::close(inheritable);
  std::ifstream in(log("fds.log"));
  std::stringstream listing;
  listing << in.rdbuf();
  // /bin/sh's own: 0, 1, 2, and the directory ls reads is ls's, not the shell's.
  EXPECT_EQ(listing.str(), "0\n1\n2\n") << "descriptors of the shell: " << listing.str();
}

}  // namespace
}  // namespace retreat::launch
