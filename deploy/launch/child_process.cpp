#include "retreat/launch/child_process.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
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

namespace {

/// What the child needs between clone() and execve(), all prepared by the parent.
struct ChildSetup {
  char* const* argv;
  char* const* envp;
  int null_fd;
  int log_fd;
  pid_t parent;
  int exec_errno = 0;  ///< set by the child if execve failed; the parent reads it once clone returns
};

/// The child, from clone() to execve(). It runs in the launcher's memory (CLONE_VM) while the
/// launcher's thread waits (CLONE_VFORK), so it only makes system calls and writes nothing of
/// the launcher's but ChildSetup::exec_errno.
int exec_child(void* arg) {
  auto& c = *static_cast<ChildSetup*>(arg);
  // The launcher's signal handlers must not run here, in its memory: every caught signal goes
  // back to its default (as execve would do) before the mask, all blocked by the parent, is
  // cleared. Ignored signals stay ignored, as across execve.
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  for (int signo = 1; signo < NSIG; ++signo) {
    struct sigaction current {};
    if (::sigaction(signo, nullptr, &current) == 0 && current.sa_handler != SIG_DFL && current.sa_handler != SIG_IGN) {
      ::sigaction(signo, &default_action, nullptr);
    }
  }
  ::setpgid(0, 0);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // the launcher died: stop too
  if (::getppid() != c.parent) ::_exit(127);  // it died before prctl
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::dup2(c.null_fd, 0);
  ::dup2(c.log_fd, 1);
  ::dup2(c.log_fd, 2);
  // Close every other descriptor (middleware sockets of the launcher, other children's log
  // files): two system calls, not a thousand.
  if (::close_range(3, ~0U, 0) != 0) {
    for (int fd = 3; fd < 1024; ++fd) ::close(fd);
  }
  ::execve(c.argv[0], c.argv, c.envp);
  c.exec_errno = errno;
  ::_exit(127);
}

}  // namespace

ChildProcess::ChildProcess(std::string name, const std::vector<std::string>& argv,
                           const std::string& log_path, const std::vector<std::string>& extra_env)
    : name_(std::move(name)), log_path_(log_path) {
  // Everything the child needs is prepared before clone(): after it, the child may only make
  // system calls (it shares the launcher's memory, and the launcher has middleware threads).
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
  if (null_fd < 0) {
    const int e = errno;
    ::close(log_fd);
    throw std::runtime_error(std::string("cannot start a child: ") + std::strerror(e));
  }
  ChildSetup setup{args.data(), env.data(), null_fd, log_fd, ::getpid()};
  // clone(CLONE_VM | CLONE_VFORK), as posix_spawn does (which cannot set PR_SET_PDEATHSIG): no
  // copy of the launcher's page tables and no copy-on-write faults after it, and this thread
  // resumes once the child has executed its program or failed to, so a program that cannot run
  // is reported here. All signals are blocked until then (exec_child clears the child's mask).
  // The child's stack until execve, a few system calls deep; not zeroed, so that no page of it is
  // touched but those the child uses.
  constexpr std::size_t stack_size = 64 * 1024;
  const auto stack = std::make_unique_for_overwrite<char[]>(stack_size);
  sigset_t all;
  sigset_t previous;
  sigfillset(&all);
  ::pthread_sigmask(SIG_SETMASK, &all, &previous);
  const pid_t pid = ::clone(exec_child, stack.get() + stack_size, CLONE_VM | CLONE_VFORK | SIGCHLD, &setup);
  const int clone_errno = errno;
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  ::close(log_fd);
  ::close(null_fd);
  if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(clone_errno));
  pid_ = pid;
  if (setup.exec_errno != 0) {
    int status = 0;
    ::waitpid(pid_, &status, 0);
    status_ = ExitStatus{127, 0};
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(setup.exec_errno));
  }
}

ChildProcess::~ChildProcess() {
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
      status_(other.status_) {
  other.pid_ = -1;
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
