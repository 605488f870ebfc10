#pragma once
/// @file
/// Runs retreat-launch as a child process (by path; stopped by PID) and reads what it wrote:
/// the experiments reuse the launcher's runs rather than re-implementing them.

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "retreat/experiment/common.hpp"

namespace retreat::experiment {

/// The signal (SIGINT, SIGTERM, SIGHUP) that asked retreat-experiment to stop; 0 while none did.
extern std::atomic<int> stop_signal;

/// Thrown when a signal stopped a run (the child has been stopped): exit 128 + signal.
struct Stopped {
  int signo = 0;
};

/// One retreat-launch invocation: `scenario` over `seeds` into `out` (OUT/seed_<n>/).
struct LaunchRequest {
  std::string scenario;
  std::vector<std::string> overrides;  ///< each passed as --set
  SeedRange seeds;
  bool in_process = true;
  std::string dds;            ///< process mode: fastdds or cyclonedds
  std::optional<int> domain;  ///< process mode: the DDS domain (default: the launcher picks)
  std::string out;
  std::string log;  ///< the launcher's output
  std::optional<unsigned> jobs = {};  ///< in process: seeds at once (--jobs); empty: its default
};

/// Runs retreat-launch (`launcher`, a path) to its end. On SIGINT/SIGTERM/SIGHUP it is sent
/// SIGTERM (it stops its own children first), then Stopped is thrown. Throws RunFailure when it
/// exits with a code other than 0 (the message names the log), UsageError on exit code 2.
void run_launch(const std::string& launcher, const LaunchRequest& request);

}  // namespace retreat::experiment
