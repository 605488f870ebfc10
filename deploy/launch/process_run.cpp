// Process mode: one retreat-arena, one retreat-agent per robot, and the bridge when there is
// one, each its own process and DDS participant, supervised by PID until the arena exits.

#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "retreat/launch/child_process.hpp"
#include "progress.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/transport/factory.hpp"
#include "run.hpp"
#include "shared_memory.hpp"
#include "summary.hpp"

namespace retreat::launch {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr auto agent_stagger = 5ms;
constexpr auto arena_stop_grace = 10s;  // it writes the run directory's summary on SIGTERM
constexpr auto child_stop_grace = 5s;
/// A bridge that dies mid-run is restarted (it appends to agent_status.csv; telemetry.csv is
/// the arena's), at most this many times: a bridge that keeps dying is left dead.
constexpr std::uint32_t max_bridge_restarts = 10;
/// An arena killed by a signal is restarted with --resume (it rebuilds its world from the run
/// directory; the agents keep running and see a pause), at most this often. Lockstep and real
/// time alike: in lockstep the run then has the uninterrupted trajectory, since the agents'
/// decision writers keep at most a few decisions for the dead arena and never block on it
/// (transport::QosIntent::answers()). An arena that exits with an error code is not restarted.
constexpr std::uint32_t max_arena_restarts = 5;

struct AgentProcess {
  std::uint32_t robot;
  std::string vendor;
  std::string program;  ///< retreat-agent, or retreat-agent-<vendor> (agent_program)
  std::unique_ptr<ChildProcess> process;
  bool reported = false;  ///< its exit has been reported
};

/// The launcher's own view of the run: a reader of `<prefix>/arena_telemetry` on its own
/// participant (the arena's vendor). Progress only: correctness never depends on it.
class TelemetryWatch {
 public:
  TelemetryWatch(const scenario::Scenario& s, const std::string& vendor, int domain) {
    // Secure swarm: the launcher reads telemetry with the bridge's identity (read-only).
    auto o = scenario::participant_options(s, "retreat-launch", "retreat:launch", "bridge");
    o.domain_id = domain;
    o.domains = 1;  // telemetry is written on the swarm's first domain
    transport_ = transport::make_transport(vendor, o);
    reader_.emplace(transport_->create_reader<wire::ArenaTelemetry>(
        {wire::arena_telemetry_topic(s.dds.prefix), transport::QosIntent::newest()}));
  }
  /// Returns the newest telemetry sample received, if any. Until the first one, waits up to
  /// `timeout` for it (the start-up is timed to it); from then on sleeps `timeout` and takes what
  /// came. The arena publishes 10 samples per simulated second, 13,000 per wall second in a fast
  /// lockstep run, and waking for each cost robotarium-2019 over Fast DDS about a quarter of its
  /// run (docs/benchmarks.md, "The launcher's progress without a wake per sample").
  std::optional<wire::ArenaTelemetry> poll(std::chrono::milliseconds timeout) {
    if (seen_) {
      std::this_thread::sleep_for(timeout);
    } else {
      transport_->wait(timeout);
    }
    auto samples = reader_->take();
    if (samples.empty()) return std::nullopt;
    seen_ = true;
    return samples.back();
  }

 private:
  std::unique_ptr<transport::Transport> transport_;
  std::optional<transport::Reader<wire::ArenaTelemetry>> reader_;
  bool seen_ = false;  ///< a sample has arrived
};

void write_processes(const std::string& dir, int domain, const ChildProcess& arena,
                     const std::string& arena_vendor, const std::vector<AgentProcess>& agents,
                     const ChildProcess* bridge) {
  nlohmann::json j;
  j["launcher_pid"] = ::getpid();
  j["domain"] = domain;
  j["arena"] = {{"pid", arena.pid()}, {"vendor", arena_vendor}, {"log", arena.log_path()}};
  j["agents"] = nlohmann::json::array();
  for (const auto& a : agents) {
    j["agents"].push_back({{"robot", a.robot}, {"pid", a.process->pid()}, {"vendor", a.vendor},
                           {"program", a.program}, {"log", a.process->log_path()}});
  }
  j["bridge"] = bridge != nullptr ? nlohmann::json{{"pid", bridge->pid()}, {"log", bridge->log_path()}}
                                  : nlohmann::json(nullptr);
  write_json_atomically(dir + "/processes.json", j);
}

std::string kib(std::uint64_t bytes) { return std::to_string(bytes / 1024) + " KiB"; }

/// Before every launch: stale Fast DDS segments go (their owners are dead), and with a Fast DDS
/// profile that uses shared memory a /dev/shm too full for every Fast DDS process of the run is
/// refused in one line (std::invalid_argument: exit 2), since they would die of SIGBUS.
void prepare_shared_memory(const Plan& plan, const scenario::Scenario& s, std::uint32_t agents,
                           ProgressLine& progress) {
  const std::string shm = "/dev/shm";
  const auto cleaned = remove_stale_fastdds_segments(shm);
  if (cleaned.segments > 0) {
    progress.message("retreat-launch: removed " + std::to_string(cleaned.segments) +
                     " stale Fast DDS shared-memory segments (" + kib(cleaned.bytes) + ") from " + shm);
  }
  const bool fast_arena = plan.vendors.arena == "fastdds";
  const std::string arena_profile =
      plan.options.arena_profile.empty() ? s.dds.profile : plan.options.arena_profile;
  std::uint32_t users = fast_arena && profile_uses_shared_memory(arena_profile) ? 1 : 0;
  if (profile_uses_shared_memory(s.dds.profile)) {
    // The launcher's own telemetry reader and the bridge use the arena's vendor.
    if (fast_arena) users += plan.bridge_exe.empty() ? 1 : 2;
    for (std::uint32_t r = 0; r < agents; ++r) users += plan.vendors.agent(r) == "fastdds" ? 1 : 0;
  }
  const auto need = users * shm_bytes_per_participant;
  const auto free = free_bytes(shm);
  if (users > 0 && free < need) {
    throw std::invalid_argument(
        shm + " has " + kib(free) + " free; the " + std::to_string(users) +
        " Fast DDS processes of this run use shared memory (dds.profile " +
        (profile_uses_shared_memory(s.dds.profile) ? s.dds.profile : arena_profile) + ") and need about " +
        kib(need) + ", or die of SIGBUS: free " + shm +
        " or use a profile without shared memory (deploy/dds/fastdds-loopback.xml)");
  }
}

}  // namespace

RunOutcome run_processes(const Plan& plan, std::uint64_t seed, const std::string& dir, int domain) {
  namespace fs = std::filesystem;
  const auto launch_start = Clock::now();
  const auto s = scenario::load(plan.options.scenario_path, overrides_for_seed(plan, seed));
  fs::create_directories(dir + "/logs");
  const std::string scenario_path = fs::absolute(plan.options.scenario_path).string();
  const std::string domain_text = std::to_string(domain);
  std::vector<std::string> common = {"--scenario", scenario_path, "--domain", domain_text};
  for (const auto& o : overrides_for_seed(plan, seed)) {
    common.push_back("--set");
    common.push_back(o);
  }
  auto with = [&](std::vector<std::string> head) {
    head.insert(head.end(), common.begin(), common.end());
    return head;
  };

  ProgressLine progress(s.name + " seed " + std::to_string(seed), s.run.duration);
  prepare_shared_memory(plan, s, agent_processes(plan, s), progress);
  std::unique_ptr<ChildProcess> arena, bridge, recorder;
  const std::string recording = recording_path(plan, seed);
  std::vector<AgentProcess> agents;
  std::map<std::string, std::uint32_t> agent_vendors;
  const auto all_children = [&] {
    std::vector<ChildProcess*> out;
    if (arena) out.push_back(arena.get());
    for (auto& a : agents) out.push_back(a.process.get());
    if (bridge) out.push_back(bridge.get());
    if (recorder) out.push_back(recorder.get());
    return out;
  };
  const auto start_agent = [&](std::uint32_t robot) {
    const auto vendor = plan.vendors.agent(robot);
    const auto& program = agent_program(plan, vendor);
    auto p = std::make_unique<ChildProcess>(
        "retreat-agent robot " + std::to_string(robot),
        with({program, "--robot-id", std::to_string(robot), "--dds", vendor}),
        dir + "/logs/agent_" + std::to_string(robot) + ".log");
    agents.push_back({robot, vendor, program, std::move(p)});
    ++agent_vendors[vendor];
  };

  bool stopped = false;
  std::uint32_t bridge_restarts = 0;
  std::uint32_t arena_restarts = 0;
  std::optional<ExitStatus> arena_status;
  std::optional<double> first_tick_seconds;
  try {
    // The arena first: it waits for the agents itself (run.startup_timeout), and with Fast DDS
    // its low participant index keeps it among every agent's initial unicast peers.
    auto arena_args = with({plan.arena_exe, "--dds", plan.vendors.arena, "--out", dir});
    if (!plan.options.arena_profile.empty()) {
      arena_args.push_back("--set");  // after the user's --set: this one wins
      arena_args.push_back("dds.profile=" + fs::absolute(plan.options.arena_profile).string());
    }
    arena = std::make_unique<ChildProcess>("retreat-arena", arena_args, dir + "/logs/arena.log");
    // Agents of a Cyclone star announce themselves to participant indices 0 (the hub: the arena),
    // 1 and 2 only (deploy/dds/cyclonedds-star-agent.xml): the bridge and the recorder, which read
    // every agent's topics, run the hub's file as indices 1 and 2. (A Fast DDS star's clients
    // learn every endpoint they match from the server: they keep the swarm's client profile.)
    const bool cyclone_star = plan.vendors.arena == "cyclonedds" && !plan.options.arena_profile.empty();
    const auto observer = [&](std::vector<std::string> args, int star_index) {
      std::vector<std::string> env;
      if (cyclone_star) {
        args.push_back("--set");
        args.push_back("dds.profile=" + fs::absolute(plan.options.arena_profile).string());
        env.push_back("RETREAT_DDS_PARTICIPANT_INDEX=" + std::to_string(star_index));
      }
      return std::pair{std::move(args), std::move(env)};
    };
    if (!recording.empty()) {
      // Second, so that it has a low participant index too; the arena and every agent wait for
      // it to match their writers (run.recorders = 1) before their robot's traffic begins.
      auto [args, env] = observer(with({plan.record_exe, "--dds", plan.vendors.arena, "--out", recording}), 2);
      recorder = std::make_unique<ChildProcess>("retreat-record", args, dir + "/logs/record.log", env);
    }
    const std::uint32_t robots = agent_processes(plan, s);
    for (std::uint32_t r = 0; r < robots && stop_signal.load() == 0; ++r) {
      std::this_thread::sleep_for(agent_stagger);
      start_agent(r);
    }
    const auto start_bridge = [&] {
      const std::string log = bridge_restarts == 0
                                  ? "bridge.log"
                                  : "bridge.restart_" + std::to_string(bridge_restarts) + ".log";
      auto [args, env] = observer(with({plan.bridge_exe, "--dds", plan.vendors.arena, "--out", dir}), 1);
      bridge = std::make_unique<ChildProcess>("retreat-bridge", args, dir + "/logs/" + log, env);
    };
    if (!plan.bridge_exe.empty() && stop_signal.load() == 0) start_bridge();
    write_processes(dir, domain, *arena, plan.vendors.arena, agents, bridge.get());

    std::unique_ptr<TelemetryWatch> watch;
    try {
      watch = std::make_unique<TelemetryWatch>(s, plan.vendors.arena, domain);
    } catch (const std::exception& e) {
      progress.message("retreat-launch: no progress line (cannot read the arena's telemetry: " +
                       std::string(e.what()) + ")");
    }
    progress.show_status("waiting for the arena to match " + std::to_string(agents.size()) + " agents");
    bool bridge_reported = false;
    bool recorder_reported = false;
    for (;;) {
      if (stop_signal.load() != 0) {
        stopped = true;
        break;
      }
      if (const auto& st = arena->poll()) {
        if (st->signal == 0 || arena_restarts == max_arena_restarts) break;
        ++arena_restarts;
        const std::string log = dir + "/logs/arena.restart_" + std::to_string(arena_restarts) + ".log";
        progress.message("retreat-launch: retreat-arena (pid " + std::to_string(arena->pid()) + ") " +
                         st->describe() + "; restarting it with --resume (" + log + ")");
        auto resume_args = arena_args;
        resume_args.push_back("--resume");
        arena = std::make_unique<ChildProcess>("retreat-arena", resume_args, log);
        write_processes(dir, domain, *arena, plan.vendors.arena, agents, bridge.get());
        continue;
      }
      // Every agent's process state once per pass: a pass takes 100 ms (the telemetry watch looks
      // that often, not at every sample), so a thousand agents cost 10,000 waitpid() a second.
      for (auto& a : agents) {
        const auto& st = a.process->poll();
        if (!st || a.reported) continue;
        a.reported = true;
        // Exit code 0: its robot departed. Anything else: the arena counts the agent lost.
        if (st->code != 0) {
          progress.message("retreat-launch: retreat-agent robot " + std::to_string(a.robot) + " (pid " +
                           std::to_string(a.process->pid()) + ") " + st->describe() +
                           "; the arena will count it lost (" + a.process->log_path() + ")");
        }
      }
      if (recorder && !recorder_reported && recorder->poll()) {
        recorder_reported = true;  // not restarted: a second recorder would start a new file
        progress.message("retreat-launch: retreat-record (pid " + std::to_string(recorder->pid()) + ") " +
                         recorder->poll()->describe() + " (" + recorder->log_path() +
                         "); the run goes on unrecorded");
      }
      if (bridge && !bridge_reported && bridge->poll()) {
        const bool restart = bridge_restarts < max_bridge_restarts;
        progress.message("retreat-launch: retreat-bridge (pid " + std::to_string(bridge->pid()) +
                         ") " + bridge->poll()->describe() + " (" + bridge->log_path() + "); " +
                         (restart ? "restarting it" : "the run goes on without it"));
        if (restart) {
          ++bridge_restarts;
          start_bridge();
          write_processes(dir, domain, *arena, plan.vendors.arena, agents, bridge.get());
        } else {
          bridge_reported = true;
        }
      }
      std::optional<wire::ArenaTelemetry> t;
      if (watch) {
        t = watch->poll(100ms);
      } else {
        std::this_thread::sleep_for(100ms);
      }
      if (!t) continue;
      if (!first_tick_seconds) {
        // The arena publishes tick 0 once it has matched the agents (or given up on some).
        first_tick_seconds = std::chrono::duration<double>(Clock::now() - launch_start).count();
      }
      progress.show(*t);
      if (plan.endless) {
        // Ids only grow, one per robot: inside + waiting + retreating + departed of them exist.
        const std::uint32_t exist = t->inside + t->waiting + t->retreating + t->departed;
        const auto before = agents.size();
        for (auto r = static_cast<std::uint32_t>(agents.size()); r < exist + endless_spare_agents; ++r) start_agent(r);
        if (agents.size() != before) write_processes(dir, domain, *arena, plan.vendors.arena, agents, bridge.get());
      }
    }
    watch.reset();
    if (stopped) {
      // The arena first, so that it writes its summary; then everything else.
      stop_all({arena.get()}, arena_stop_grace);
    }
    arena_status = arena->poll();
    std::vector<ChildProcess*> agent_children;
    for (auto& a : agents) agent_children.push_back(a.process.get());
    stop_all(agent_children, child_stop_grace);
  } catch (...) {
    stop_all(all_children(), child_stop_grace);
    throw;
  }
  progress.finish();
  // The recorder once every agent has ended (their last samples are acknowledged by then).
  std::string recorder_exit;
  if (recorder) {
    stop_all({recorder.get()}, child_stop_grace);
    const auto st = recorder->poll();
    recorder_exit = st ? st->describe() : "still running";
    if (!st || st->signal != 0 || st->code != 0) {
      progress.message("retreat-launch: retreat-record (pid " + std::to_string(recorder->pid()) + ") " +
                       recorder_exit + ": the recording " + recording + " may be incomplete (" +
                       recorder->log_path() + ")");
    }
  }
  // The bridge goes last, once summary.json is complete: it writes its report on SIGTERM.
  struct StopBridge {
    ChildProcess* bridge;
    ~StopBridge() {
      if (bridge != nullptr) stop_all({bridge}, child_stop_grace);
    }
  } stop_bridge{bridge.get()};

  if (!stopped && (arena_status->signal != 0 || arena_status->code != 0)) {
    throw RunFailure("retreat-arena (pid " + std::to_string(arena->pid()) + ") " + arena_status->describe() +
                     "; stopped every agent (see " + arena->log_path() + ")");
  }
  LaunchRecord record;
  record.dds = plan.vendors.label;
  record.mode = "processes";
  record.agents_started = static_cast<std::uint32_t>(agents.size());
  record.wall_seconds = std::chrono::duration<double>(Clock::now() - launch_start).count();
  record.domain = domain;
  record.arena_vendor = plan.vendors.arena;
  record.agent_vendors = agent_vendors;
  record.bridge = bridge != nullptr;
  record.bridge_restarts = bridge_restarts;
  record.arena_restarts = arena_restarts;
  record.seconds_to_first_tick = first_tick_seconds.value_or(-1.0);
  if (rusage children{}; ::getrusage(RUSAGE_CHILDREN, &children) == 0) {
    const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
    record.children_user_seconds = seconds(children.ru_utime);
    record.children_system_seconds = seconds(children.ru_stime);
  }
  record.recording = recording;
  record.recorder_exit = recorder_exit;
  RunOutcome out;
  out.stopped = stopped;
  if (stopped && !fs::exists(dir + "/summary.json")) return out;
  out.summary = update_summary(dir, record);
  return out;
}

}  // namespace retreat::launch
