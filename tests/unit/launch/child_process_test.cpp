// The launcher's child processes (retreat/launch/child_process.hpp): a program that cannot be
// executed is reported by the constructor; a child starts with no signal blocked and inherits no
// descriptor of the launcher but stdin, stdout and stderr.

#include "retreat/launch/child_process.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
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

TEST_F(ChildProcessTest, AProgramThatRunsEndsWithItsOwnCode) {
  ChildProcess child("sh", {"/bin/sh", "-c", "exit 7"}, log("sh.log"));
  EXPECT_EQ(wait_for_exit(child).code, 7);
}

// The constructor blocks every signal while the child shares the launcher's memory: the child
// clears its mask before its program runs, and the launcher's thread gets its own mask back.
TEST_F(ChildProcessTest, AChildStartsWithNoSignalBlockedAndTheLauncherKeepsItsOwnMask) {
  sigset_t usr2;
  sigemptyset(&usr2);
  sigaddset(&usr2, SIGUSR2);
  sigset_t before;
  ASSERT_EQ(::pthread_sigmask(SIG_BLOCK, &usr2, &before), 0);
  // grep itself, not a shell: dash clears its signal mask when it starts.
  ChildProcess child("mask", {"/bin/grep", "SigBlk", "/proc/self/status"}, log("mask.log"));
  sigset_t after;
  ::pthread_sigmask(SIG_SETMASK, &before, &after);
  EXPECT_EQ(wait_for_exit(child).code, 0);
  EXPECT_EQ(sigismember(&after, SIGUSR2), 1) << "the launcher's own blocked signal";
  EXPECT_EQ(sigismember(&after, SIGUSR1), 0) << "the constructor's all-blocked mask left behind";
  std::ifstream in(log("mask.log"));
  std::stringstream status;
  status << in.rdbuf();
  EXPECT_EQ(status.str(), "SigBlk:\t0000000000000000\n");
}

// The launcher's own descriptors (a DDS socket, a log file: here a file opened
// without close-on-exec) are closed in the child before its program runs.
TEST_F(ChildProcessTest, AChildInheritsOnlyStdinStdoutAndStderr) {
  const int inheritable = ::open("/dev/null", O_RDONLY);  // deliberately without O_CLOEXEC
  ASSERT_GE(inheritable, 3);
  ChildProcess child("fds", {"/bin/sh", "-c", "ls /proc/$$/fd"}, log("fds.log"));
  EXPECT_EQ(wait_for_exit(child).code, 0);
  ::close(inheritable);
  std::ifstream in(log("fds.log"));
  std::stringstream listing;
  listing << in.rdbuf();
  // /bin/sh's own: 0, 1, 2, and the directory ls reads is ls's, not the shell's.
  EXPECT_EQ(listing.str(), "0\n1\n2\n") << "descriptors of the shell: " << listing.str();
}

}  // namespace
}  // namespace retreat::launch
