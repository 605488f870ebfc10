#pragma once
/// @file
/// Child processes of the launcher: started by path, supervised and stopped by PID, never by
/// name. Each child runs in its own process group (a Ctrl-C on the terminal reaches only the
/// launcher, which then stops the children in order) and gets SIGTERM if the launcher dies.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace retreat::launch {

/// How a child ended.
struct ExitStatus {
  int code = 0;    ///< exit code, or 128 + signal
  int signal = 0;  ///< the signal that killed it, 0 if it exited
  std::string describe() const;  ///< "exited with code 3", "was killed by signal 9 (Killed)"
};

class ChildProcess {
 public:
  /// Starts `argv[0]` (a path) with stdin from /dev/null and stdout+stderr into `log_path`, in
  /// the launcher's environment plus `extra_env` ("NAME=value" each, replacing a variable of the
  /// same name). Returns once the child has executed its program; throws std::runtime_error
  /// when the program cannot be started (the failed child is reaped).
  ChildProcess(std::string name, const std::vector<std::string>& argv, const std::string& log_path,
               const std::vector<std::string>& extra_env = {});
  ~ChildProcess();  ///< kills (SIGKILL) and reaps a child still running
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  const std::string& name() const { return name_; }
  pid_t pid() const { return pid_; }
  const std::string& log_path() const { return log_path_; }

  /// Reaps the child if it has ended (never blocks); returns how it ended, if it has.
  const std::optional<ExitStatus>& poll();
  bool running() { return !poll().has_value(); }
  /// Sends `signo` to this child's PID (nothing if it has been reaped).
  void signal(int signo);

 private:
  std::string name_;
  std::string log_path_;
  pid_t pid_ = -1;
  std::optional<ExitStatus> status_;
};

/// SIGTERM to every running child, then SIGKILL to those still running after `grace`; reaps
/// them all. Returns when none is left.
void stop_all(const std::vector<ChildProcess*>& children, std::chrono::milliseconds grace);

}  // namespace retreat::launch
