// retreat-launch: runs a scenario as a swarm on one machine: one retreat-arena, one
// retreat-agent per robot and the retreat-bridge (when built), each its own process and DDS
// participant; or all of it in this one process over the in-memory transport (--in-process).
//
// Reads:  SCENARIO.yaml (and each --set); in process mode <prefix>/arena_telemetry (its own
//         participant, the arena's vendor; for the progress line only).
// Writes: the run directory OUT (default runs/<timestamp>), or OUT/seed_<n>/ per seed with
//         --seeds A:B plus OUT/seeds_summary.json:
//           logs/arena.log, logs/agent_<id>.log, logs/bridge.log   (process mode)
//           processes.json   (PIDs, vendors and logs of the children; process mode)
//           scenario.yaml, telemetry.csv, agents.csv, summary.json  (by the arena, or in-process)
//           summary.json gains dds, agents.started, agents.matched and launch.* from the launcher.
//         /tmp/retreat-domain-<id>.lock, held (flock) while a process-mode run uses domain <id>.
//
// Exit codes: 0 every run completed; 1 a run failed (the arena failed or left no summary);
// 2 bad input (nothing was started); 128 + signal when SIGINT/SIGTERM/SIGHUP stopped it (every
// child is stopped first, and the summary updated when the arena wrote one).

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
#include <thread>
#include <variant>
#include <vector>

#include "retreat/arena/run_recorder.hpp"
#include "retreat/launch/command_line.hpp"
#include "retreat/launch/capacity.hpp"
#include "domain_lock.hpp"
#include "retreat/launch/options.hpp"
#include "retreat/core/paths.hpp"
#include "retreat/scenario/program_options.hpp"
#include "run.hpp"
#include "summary.hpp"

namespace retreat::launch {
std::atomic<int> stop_signal{0};
}  // namespace retreat::launch

namespace {

using namespace retreat;

extern "C" void on_signal(int signo) { launch::stop_signal.store(signo); }

/// Domains a launcher picks by itself (0 is every tool's default). Tests always name theirs.
constexpr int first_free_domain = 1;
constexpr int last_free_domain = 99;

std::string self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

std::string default_out_dir() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  std::string dir = std::string("runs/") + stamp;
  for (int n = 2; retreat::exists(dir); ++n)
    dir = std::string("runs/") + stamp + "-" + std::to_string(n);
  return dir;
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: sleeps and waits return early
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
}

void report(const nlohmann::json& j, const std::string& dir) {
  using ptr = nlohmann::json::json_pointer;
  const auto hash = j.value("trajectory_sha256", std::string());
  // Robots still driving out at the end, and for how long: minutes mean a jam
  // (docs/experiments.md, "Retreats that never end").
  std::string under_way;
  if (const int n = j.value(ptr("/retreats/under_way"), 0); n > 0) {
    char text[96];
    std::snprintf(text, sizeof text, ", %d still driving out (the longest for %.0f s)", n,
                  j.value(ptr("/retreats/longest_under_way_seconds"), 0.0));
    under_way = text;
  }
  std::fprintf(stderr,
               "retreat-launch: %s seed %llu done: %lld ticks in %.1f s (%.0f ticks/s), population "
               "%d (mean of the last 300 s %.2f, optimum %.2f)%s, %d agents lost, %lld deliveries, "
               "trajectory %s; %s/summary.json\n",
               j.value("scenario", std::string()).c_str(),
               static_cast<unsigned long long>(j.value("seed", 0ull)), j.value("ticks", 0ll),
               j.value("wall_seconds", 0.0), j.value("ticks_per_second", 0.0),
               j.value(nlohmann::json::json_pointer("/population/final"), 0),
               j.value(nlohmann::json::json_pointer("/population/mean_last_300s"), 0.0),
               j.value("optimal_population", 0.0), under_way.c_str(),
               j.value(nlohmann::json::json_pointer("/agents/lost"), 0), j.value("deliveries", 0ll),
               hash.substr(0, 16).c_str(), dir.c_str());
}

/// Process mode: the DDS domain this run holds while it runs (--domain, or a free one in
/// 1..99). An empty optional after a one-line refusal.
std::optional<launch::DomainLock> lock_domain(const launch::Plan& plan) {
  const int domains = plan.scenario.dds.domains;
  if (plan.domain) {
    auto lock = launch::DomainLock::try_lock(*plan.domain, domains);
    if (!lock) {
      std::fprintf(stderr,
                   "retreat-launch: --domain %d: another retreat-launch run on this host "
                   "uses it%s (%s%s is locked); pick another\n",
                   *plan.domain, domains > 1 ? " or one of the next dds.domains - 1" : "",
                   launch::DomainLock::path(*plan.domain).c_str(), domains > 1 ? " or a later one" : "");
    }
    return lock;
  }
  try {
    return launch::DomainLock::pick_free(first_free_domain, last_free_domain, domains);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-launch: %s\n", e.what());
    return std::nullopt;
  }
}

/// Process mode: what is about to start, where, and where the dashboard will be.
void announce(const launch::Plan& plan, int domain, const std::string& out) {
  const std::uint32_t n = plan.scenario.arena.robots_inside + plan.scenario.arena.robots_waiting;
  std::fprintf(stderr,
               "retreat-launch: %s: retreat-arena (%s) and %u retreat-agent processes "
               "(%s)%s on DDS domain %d; run directory %s\n",
               plan.scenario.name.c_str(), plan.vendors.arena.c_str(), n, plan.vendors.label.c_str(),
               plan.endless ? " plus one per robot that joins the queue" : "", domain, out.c_str());
  if (const auto warning = launch::ephemeral_port_warning(domain, plan.scenario.dds.domains, launch::read_ephemeral_ports())) {
    std::fprintf(stderr, "retreat-launch: warning: %s\n", warning->c_str());
  }
  if (!plan.bridge_exe.empty()) {
    const auto& http = plan.scenario.bridge.http;
    std::fprintf(stderr,
                 "retreat-launch: retreat-bridge serves the dashboard on %s (logs/bridge.log "
                 "names the port when bridge.http asks for a free one) and writes report.html\n",
                 (http.ends_with(":0") ? http : "http://" + http + "/").c_str());
  }
  if (plan.bridge_missing) {
    std::fprintf(stderr,
                 "retreat-launch: no bridge is built (no retreat-bridge beside "
                 "retreat-arena); running without it (--no-bridge: quietly)\n");
  }
}

/// The run directory of the plan's seed @p i: OUT itself for one seed, OUT/seed_<n> for several.
std::string run_dir(const launch::Plan& plan, const std::string& out, std::size_t i) {
  return plan.multi_seed ? out + "/seed_" + std::to_string(plan.seeds[i]) : out;
}

/// A run directory of the plan (OUT, or OUT/seed_<n>/ and OUT/seeds_summary.json for several seeds)
/// that holds a recorded run already: the one line that refuses to overwrite it, or nothing.
std::optional<std::string> recorded_run_refusal(const launch::Plan& plan, const std::string& out) {
  std::vector<std::string> found;
  if (plan.multi_seed && retreat::exists(out + "/seeds_summary.json")) found.push_back(out + "/seeds_summary.json");
  for (std::size_t i = 0; i < plan.seeds.size(); ++i) {
    if (auto file = arena::RunRecorder::recorded_run_in(run_dir(plan, out, i)); !file.empty()) {
      found.push_back(std::move(file));
    }
  }
  if (found.empty()) return std::nullopt;
  return "--out '" + out + "': holds a recorded run (" + found.front() +
         (found.size() > 1 ? " and " + std::to_string(found.size() - 1) + " more" : std::string()) +
         "); give a new directory (a run directory is never overwritten)";
}

/// Runs every seed of the plan into `out` (OUT/seed_<n>/ for several); returns the exit code.
/// In process, @p seeds_at_once seeds (plan.jobs, or fewer when the host's memory holds fewer:
/// launch::in_process_fit) run at once, one thread each: every run has its own world, bus
/// and directory, so each is the same as it would be alone. Results are reported in seed order.
int run_seeds(const launch::Plan& plan, const std::string& out, int domain, unsigned seeds_at_once) {
  const bool in_process = plan.options.in_process;
  const std::size_t n = plan.seeds.size();
  const unsigned jobs = static_cast<unsigned>(std::min<std::size_t>(seeds_at_once, n));
  std::vector<std::optional<launch::RunOutcome>> results(n);
  std::vector<nlohmann::json> summaries;
  std::mutex mutex;  // guards results, summaries, reported, halt, failure and stderr
  std::size_t next = 0, reported = 0;
  bool halt = false, stopped = false;
  std::exception_ptr failure;
  const auto worker = [&] {
    for (;;) {
      std::size_t i = 0;
      {
        std::lock_guard lock(mutex);
        if (halt || next == n) return;
        i = next++;
      }
      std::optional<launch::RunOutcome> result;
      std::exception_ptr error;
      try {
        result = in_process ? launch::run_in_process(plan, plan.seeds[i], run_dir(plan, out, i), jobs == 1)
                            : launch::run_processes(plan, plan.seeds[i], run_dir(plan, out, i), domain);
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard lock(mutex);
      if (error) {
        if (!failure) failure = error;
        halt = true;
        continue;
      }
      if (result->stopped) halt = stopped = true;  // a signal: no seed starts after this one
      results[i] = std::move(result);
      // Report every finished run whose predecessors are reported too: seed order, as it goes.
      for (; reported < n && results[reported]; ++reported) {
        const auto& r = *results[reported];
        if (!r.summary.is_null()) {
          report(r.summary, run_dir(plan, out, reported));
          summaries.push_back(r.summary);
        }
      }
    }
  };
  if (jobs <= 1) {
    worker();
  } else {
    std::vector<std::thread> threads;
    for (unsigned j = 0; j < jobs; ++j) threads.emplace_back(worker);
    for (auto& t : threads) t.join();
  }
  if (failure) std::rethrow_exception(failure);
  if (stopped) {
    const int signo = launch::stop_signal.load();
    std::fprintf(stderr, "retreat-launch: stopped by signal %d%s\n", signo,
                 in_process ? "" : "; every child stopped");
    return 128 + signo;
  }
  if (plan.multi_seed) {
    const auto j = launch::write_seeds_summary(out, summaries);
    std::fprintf(stderr,
                 "retreat-launch: %zu seeds (%u at once): population mean of the last 300 s %.2f "
                 "± %.2f (std over seeds); %s/seeds_summary.json\n",
                 summaries.size(), jobs,
                 j.value(nlohmann::json::json_pointer("/population/mean_last_300s/mean"), 0.0),
                 j.value(nlohmann::json::json_pointer("/population/mean_last_300s/std"), 0.0),
                 out.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = scenario::parse_or_report(
      "retreat-launch", [&] { return launch::parse_command_line(argc, argv, self_dir()); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& plan = std::get<launch::LaunchCommandLine>(parsed).plan;
  if (std::get<launch::LaunchCommandLine>(parsed).print_config) {
    std::cout << scenario::dump(plan.scenario);
    return 0;
  }
  std::optional<launch::DomainLock> lock;
  unsigned seeds_at_once = plan.jobs;
  if (plan.options.in_process) {
    // Before anything starts: robots this host cannot hold are refused, not left to the OOM killer.
    const auto fit = launch::in_process_fit(plan, launch::read_host_limits());
    if (fit.refusal) {
      std::fprintf(stderr, "retreat-launch: %s\n", fit.refusal->c_str());
      return 2;
    }
    if (fit.notice) std::fprintf(stderr, "retreat-launch: %s\n", fit.notice->c_str());
    seeds_at_once = fit.jobs;
  } else {
    // Before anything starts: a run this host cannot hold is refused, not left to lose agents.
    try {
      if (const auto refusal = launch::capacity_refusal(plan, plan.scenario, launch::agent_processes(plan, plan.scenario),
                                                        launch::read_host_limits())) {
        std::fprintf(stderr, "retreat-launch: %s\n", refusal->c_str());
        return 2;
      }
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "retreat-launch: %s\n", e.what());
      return 2;
    }
    lock = lock_domain(plan);
    if (!lock) return 2;
  }
  const std::string out = plan.options.out_dir.empty() ? default_out_dir() : plan.options.out_dir;
  if (const auto refusal = recorded_run_refusal(plan, out)) {
    std::fprintf(stderr, "retreat-launch: %s\n", refusal->c_str());
    return 2;
  }
  install_signal_handlers();
  if (lock) announce(plan, lock->domain(), out);
  try {
    return run_seeds(plan, out, lock ? lock->domain() : -1, seeds_at_once);
  } catch (const launch::RunFailure& e) {
    std::fprintf(stderr, "retreat-launch: run failed: %s\n", e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "retreat-launch: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-launch: run failed: %s\n", e.what());
    return 1;
  }
}
