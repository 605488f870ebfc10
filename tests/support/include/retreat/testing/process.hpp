#pragma once
/// @file
/// Child processes for multi-process tests: started by path, stopped by PID, never by name.
/// A ChildProcess that goes out of scope while running is killed (SIGKILL) and reaped.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace retreat::testing {

/// The ceiling of every wait for something that must happen (a process to exit, a match, a
/// sample, a file): long enough that only a hang reaches it, even with the machine loaded by a
/// build beside the suite. Success returns as soon as the event happens, so a generous ceiling
/// costs nothing; a test never passes or fails by how fast the machine is.
inline constexpr std::chrono::seconds hang_ceiling{300};

class ChildProcess {
 public:
  /// Starts `argv[0]` with the given arguments; stdout and stderr go to `log_path` when given.
  /// `extra_env` entries (NAME=value) add to the caller's environment or replace a variable of it.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_path = {},
               const std::vector<std::string>& extra_env = {});
  ~ChildProcess();
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  /// Waits for the exit; returns the exit code (128 + signal when killed), nullopt on timeout.
  std::optional<int> wait_for(std::chrono::milliseconds timeout);
  /// Sends a signal to this child (by PID).
  void signal(int signo);
  /// SIGTERM, then SIGKILL after `grace`; returns the exit code.
  int stop(std::chrono::milliseconds grace = std::chrono::milliseconds(3000));

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
};

/// Reads a whole file (empty string if it cannot be read).
std::string read_file(const std::string& path);

/// Runs `argv` to its exit (SIGKILL after `timeout`) with its output in `log_path`; returns the
/// exit code (-1 on timeout) and the whole output.
std::pair<int, std::string> run_to_exit(const std::vector<std::string>& argv,
                                        const std::string& log_path,
                                        std::chrono::milliseconds timeout = hang_ceiling);

/// Repeats `predicate` every few milliseconds until it is true or `timeout` passes.
template <class Predicate>
bool eventually(Predicate&& predicate, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!predicate()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    struct timespec ts {0, 5'000'000};
    nanosleep(&ts, nullptr);
  }
  return true;
}

/// A DDS domain id for one test, from its name, inside [first, first + count): tests run in
/// parallel under ctest, each on its own domain.
int domain_for_test(const std::string& test_name, int first, int count);

}  // namespace retreat::testing
