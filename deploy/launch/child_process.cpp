#include "retreat/launch/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string_view>
#include <thread>

namespace retreat::launch {

std::string ExitStatus::describe() const {
  if (signal != 0) {
    const char* name = ::strsignal(signal);
    return "was killed by signal " + std::to_string(signal) + (name != nullptr ? std::string(" (") + name + ")" : "");
  }
  return "exited with code " + std::to_string(code);
}

ChildProcess::ChildProcess(std::string name, const std::vector<std::string>& argv,
                           const std::string& log_path, const std::vector<std::string>& extra_env,
                           ExecCheck check)
    : name_(std::move(name)), log_path_(log_path), program_(argv.empty() ? std::string() : argv[0]) {
  // Everything the child needs is prepared before fork(): after it, the child may only make
  // async-signal-safe calls (the launcher has middleware threads).
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  const auto overridden = [&](std::string_view entry) {
    const auto prefix = entry.substr(0, entry.find('=') + 1);  // "NAME="
    return std::any_of(extra_env.begin(), extra_env.end(),
                       [&](const std::string& e) { return std::string_view(e).starts_with(prefix); });
  };
  for (char** e = environ; *e != nullptr; ++e) {
    if (!overridden(*e)) env.push_back(*e);
  }
  for (const auto& e : extra_env) env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);
  const int log_fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log_fd < 0) throw std::runtime_error("cannot write '" + log_path + "': " + std::strerror(errno));
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  int report[2];  // the child writes errno here if exec fails; closed by a successful exec
  if (null_fd < 0 || ::pipe2(report, O_CLOEXEC) != 0) {
    ::close(log_fd);
    if (null_fd >= 0) ::close(null_fd);
    throw std::runtime_error(std::string("cannot start a child: ") + std::strerror(errno));
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);   // the launcher died: stop too
    if (::getppid() != parent) ::_exit(127);  // it died before prctl
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::dup2(null_fd, 0);
    ::dup2(log_fd, 1);
    ::dup2(log_fd, 2);
    // Close every other descriptor (middleware sockets of the launcher, other children's report
    // pipes) except the report pipe, which is close-on-exec. close_range: two system calls, not
    // a thousand.
    const auto keep = static_cast<unsigned>(report[1]);
    const bool closed = (keep == 3 || ::close_range(3, keep - 1, 0) == 0) && ::close_range(keep + 1, ~0U, 0) == 0;
    for (int fd = 3; !closed && fd < 1024; ++fd) {
      if (fd != report[1]) ::close(fd);
    }
    ::execve(args[0], args.data(), env.data());
    const int e = errno;
    [[maybe_unused]] const auto n = ::write(report[1], &e, sizeof e);
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::close(report[1]);
  ::close(log_fd);
  ::close(null_fd);
  if (pid < 0) {
    ::close(report[0]);
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(fork_errno));
  }
  pid_ = pid;
  exec_report_ = report[0];
  if (check == ExecCheck::at_start) confirm_started();
}

void ChildProcess::confirm_started() {
  if (exec_report_ < 0) return;
  int child_errno = 0;
  ssize_t n;
  do {
    n = ::read(exec_report_, &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  ::close(exec_report_);
  exec_report_ = -1;
  if (n == static_cast<ssize_t>(sizeof child_errno)) {
    int status = 0;
    ::waitpid(pid_, &status, 0);
    status_ = ExitStatus{127, 0};
    throw std::runtime_error("cannot start " + program_ + ": " + std::strerror(child_errno));
  }
}

ChildProcess::~ChildProcess() {
  if (exec_report_ >= 0) ::close(exec_report_);
  if (pid_ > 0 && !status_) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : name_(std::move(other.name_)),
      log_path_(std::move(other.log_path_)),
      pid_(other.pid_),
      status_(other.status_),
      exec_report_(other.exec_report_),
      program_(std::move(other.program_)) {
  other.pid_ = -1;
  other.exec_report_ = -1;
}

const std::optional<ExitStatus>& ChildProcess::poll() {
  if (status_ || pid_ <= 0) return status_;
  int status = 0;
  pid_t r;
  do {
    r = ::waitpid(pid_, &status, WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r == pid_) {
    if (WIFSIGNALED(status)) {
      status_ = ExitStatus{128 + WTERMSIG(status), WTERMSIG(status)};
    } else {
      status_ = ExitStatus{WEXITSTATUS(status), 0};
    }
  } else if (r < 0) {
    status_ = ExitStatus{127, 0};  // not our child any more: nothing left to wait for
  }
  return status_;
}

void ChildProcess::signal(int signo) {
  if (pid_ > 0 && !poll()) ::kill(pid_, signo);
}

void stop_all(const std::vector<ChildProcess*>& children, std::chrono::milliseconds grace) {
  for (auto* c : children) c->signal(SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + grace;
  auto any_running = [&] {
    bool any = false;
    for (auto* c : children) any = c->running() || any;
    return any;
  };
  while (any_running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (auto* c : children) c->signal(SIGKILL);
  while (any_running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

}  // namespace retreat::launch
