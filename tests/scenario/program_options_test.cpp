// The plumbing every program shares (retreat::program_options) beyond the scenario loader.

#include "retreat/scenario/program_options.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "retreat/testing/process.hpp"

namespace {

using namespace std::chrono_literals;

// A stop signal wakes a loop blocked in a long wait (an idle agent waits for its next frame, not
// a poll period) through the StopWakeup it registered. A wait that only the ceiling ends fails.
TEST(StopWakeup, AStopSignalWakesALongWaitAndSetsTheFlag) {
  retreat::scenario::install_stop_handlers();
  std::mutex mutex;
  std::condition_variable changed;
  bool woken = false;
  const retreat::scenario::StopWakeup wakeup([&] {
    const std::lock_guard lock(mutex);
    woken = true;
    changed.notify_all();
  });
  std::thread signaller([] { std::raise(SIGTERM); });
  std::unique_lock lock(mutex);
  EXPECT_TRUE(changed.wait_for(lock, retreat::testing::hang_ceiling, [&] { return woken; }));
  EXPECT_TRUE(retreat::scenario::stop_requested());
  lock.unlock();
  signaller.join();
}

// A wakeup registered after the stop was signalled is called at once: a stop between the
// check of the flag and the registration is not missed.
TEST(StopWakeup, ARegistrationAfterTheStopIsWokenAtOnce) {
  retreat::scenario::install_stop_handlers();
  std::atomic<int> calls{0};
  {
    const retreat::scenario::StopWakeup first([&] { ++calls; });
    std::raise(SIGTERM);
    // The signal handler only writes the pipe; the watcher's thread calls the wakes.
    while (calls.load() == 0) std::this_thread::sleep_for(1ms);
  }
  const retreat::scenario::StopWakeup late([&] { ++calls; });
  EXPECT_EQ(calls.load(), 2);
}

// A teardown that never ends (as a Fast DDS participant deletion once did) is cut short: one line
// naming the program, and the exit code the program chose. Runs in a forked child (death test).
TEST(LimitTeardownDeathTest, AProcessStillTearingDownAfterTheLimitExitsWithOneLine) {
  EXPECT_EXIT(
      {
        retreat::scenario::limit_teardown("some-program", 1s, 3);
        std::this_thread::sleep_for(60s);  // the hung teardown
      },
      ::testing::ExitedWithCode(3), "some-program: teardown still running after 1 s");
}

// A process that finishes in time exits with its own code: the deadline does not interfere.
TEST(LimitTeardownDeathTest, AProcessThatExitsInTimeKeepsItsOwnExitCode) {
  EXPECT_EXIT(
      {
        retreat::scenario::limit_teardown("some-program", 30s, 3);
        std::exit(0);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
