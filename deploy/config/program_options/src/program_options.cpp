#include "retreat/scenario/program_options.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

namespace retreat::scenario {

void add_common_options(CLI::App& app, CommonOptions& options, bool positional_scenario) {
  if (positional_scenario) {
    app.add_option("scenario", options.scenario_path, "scenario file (YAML)")->required();
  } else {
    app.add_option("--scenario", options.scenario_path, "scenario file (YAML)")->required();
  }
  app.add_option("--dds", options.dds, "middleware: fastdds or cyclonedds (overrides dds.vendor)");
  add_whole_number(app, "--domain", options.domain, "DDS domain id 0..232 (overrides dds.domain)", 0,
                   transport::max_domain_id);
  app.add_option("--set", options.overrides,
                 "override a scenario value: section.key=value (repeatable)")
      ->allow_extra_args(false);
  app.add_flag("--print-config", options.print_config, "print the resolved scenario and exit");
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      std::string_view program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    report_error(program, e.what());
    return 2;
  }
  return std::nullopt;
}

namespace {

bool parse_u64(const std::string& text, std::uint64_t& value) {
  const char* first = text.data();
  const char* last = first + text.size();
  const auto [end, error] = std::from_chars(first, last, value);
  return error == std::errc() && end == last && first != last;
}

}  // namespace

SeedRange parse_seed_range(const std::string& text, const std::string& option) {
  const auto colon = text.find(':');
  SeedRange r;
  if (colon == std::string::npos || !parse_u64(text.substr(0, colon), r.first) ||
      !parse_u64(text.substr(colon + 1), r.last) || r.first > r.last) {
    throw ConfigError(option + " '" + text + "': must be A:B with whole numbers 0 <= A <= B");
  }
  if (r.last - r.first >= 100000)
    throw ConfigError(option + " '" + text + "': at most 100000 seeds");
  return r;
}

unsigned core_count() { return std::max(1u, std::thread::hardware_concurrency()); }

void check_jobs(unsigned jobs) {
  if (jobs < 1 || jobs > max_jobs) {
    throw ConfigError("--jobs " + std::to_string(jobs) + ": must be an integer in 1.." + std::to_string(max_jobs));
  }
}

Scenario load_scenario(const CommonOptions& options) {
  auto overrides = options.overrides;
  if (!options.dds.empty()) overrides.push_back("dds.vendor=" + options.dds);
  if (options.domain != -1) overrides.push_back("dds.domain=" + std::to_string(options.domain));
  return load(options.scenario_path, overrides);
}

void report_error(std::string_view program, std::string_view message) {
  std::fprintf(stderr, "%.*s: %.*s\n", static_cast<int>(program.size()), program.data(),
               static_cast<int>(message.size()), message.data());
}

transport::ParticipantOptions participant_options(const Scenario& s, std::string name,
                                                  std::string user_data,
                                                  const std::string& identity) {
  transport::ParticipantOptions options;
  options.domain_id = s.dds.domain;
  options.domains = s.dds.domains;
  options.name = std::move(name);
  options.user_data = std::move(user_data);
  options.profile = s.dds.profile;
  if (s.dds.security == Security::on) options.security = transport::swarm_identity(s.dds.security_dir, identity);
  return options;
}

transport::ParticipantOptions robot_participant_options(const Scenario& s, wire::RobotId robot, std::string name,
                                                        std::string user_data, const std::string& identity) {
  auto options = participant_options(s, std::move(name), std::move(user_data), identity);
  options.domain_id = wire::robot_domain(s.dds.domain, s.dds.domains, robot);
  options.domain_index = options.domain_id - s.dds.domain;
  options.domains = 1;
  return options;
}

namespace {

std::atomic<bool> stop_flag{false};  // lock-free: safe to set from a signal handler
// The self-pipe: the handler writes a byte, the stop watcher's thread reads it and calls the
// StopWakeup functions (which a signal handler may not: they lock and notify).
int stop_pipe[2] = {-1, -1};

extern "C" void on_stop_signal(int) {
  stop_flag.store(true);
  const int saved_errno = errno;
  const char byte = 1;
  // write() is async-signal-safe; the write end does not block, and a full pipe already holds
  // the byte that wakes the watcher.
  [[maybe_unused]] const auto written = ::write(stop_pipe[1], &byte, 1);
  errno = saved_errno;
}

struct StopWatcher {
  std::mutex mutex;
  std::map<std::uint64_t, std::function<void()>> wakes;
  std::uint64_t next_id = 0;
  bool fired = false;
};

// Never destroyed: the watcher's thread may still be blocked reading when main returns.
StopWatcher& stop_watcher() {
  static auto* watcher = new StopWatcher;
  return *watcher;
}

void watch_stop_pipe() {
  char byte = 0;
  for (;;) {
    const auto n = ::read(stop_pipe[0], &byte, 1);
    if (n == 1) break;
    if (n < 0 && errno == EINTR) continue;
    return;  // the pipe is gone: no stop can be signalled any more
  }
  auto& watcher = stop_watcher();
  std::lock_guard lock(watcher.mutex);
  watcher.fired = true;
  for (auto& entry : watcher.wakes) entry.second();
}

}  // namespace

void install_stop_handlers() {
  static std::once_flag started;
  std::call_once(started, [] {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0 || ::fcntl(fds[1], F_SETFL, O_NONBLOCK) != 0) {
      // Not fatal: stop_requested() still works, and loops that rely on a StopWakeup wait with
      // a ceiling.
      std::fprintf(stderr, "retreat: no pipe for the stop signal (%s); a stop is noticed on the next poll\n",
                   std::strerror(errno));
      return;
    }
    stop_pipe[0] = fds[0];
    stop_pipe[1] = fds[1];
    std::thread(watch_stop_pipe).detach();
  });
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() { return stop_flag.load(); }

StopWakeup::StopWakeup(std::function<void()> wake) {
  auto& watcher = stop_watcher();
  std::lock_guard lock(watcher.mutex);
  id_ = watcher.next_id++;
  if (watcher.fired) {
    wake();
    return;
  }
  watcher.wakes.emplace(id_, std::move(wake));
}

StopWakeup::~StopWakeup() {
  auto& watcher = stop_watcher();
  std::lock_guard lock(watcher.mutex);  // after a wake in progress has returned
  watcher.wakes.erase(id_);
}

void limit_teardown(std::string_view program, std::chrono::seconds limit, int code) {
  std::thread([name = std::string(program), limit, code] {
    std::this_thread::sleep_for(limit);
    std::fprintf(stderr,
                 "%s: teardown still running after %lld s; exiting without waiting for it\n",
                 name.c_str(), static_cast<long long>(limit.count()));
    std::fflush(stderr);
    std::_Exit(code);
  }).detach();
}

}  // namespace retreat::scenario
