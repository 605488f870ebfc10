// The plumbing every program shares (retreat::program_options) beyond the scenario loader.

#include "retreat/scenario/program_options.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <thread>

namespace {

using namespace std::chrono_literals;

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
