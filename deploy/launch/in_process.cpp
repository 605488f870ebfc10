// In-process runs: the arena's and the agents' own code (retreat::arena_node,
// retreat::agent_node) in one process over the in-memory transport, stepped deterministically.
// Lockstep semantics are the multi-process ones: tick k's frames go out, every live agent
// answers tick k, then the world steps; so the trajectory hash is the same as with processes.

#include <chrono>
#include <map>
#include <memory>
#include <set>

#include "agent_node.hpp"
#include "arena_node.hpp"
#include "progress.hpp"
#include "retreat/transport/inmemory.hpp"
#include "run.hpp"
#include "summary.hpp"

namespace retreat::launch {
namespace {

struct InProcessAgent {
  std::unique_ptr<transport::Transport> transport;
  std::unique_ptr<agent::AgentNode> node;
};

wire::ArenaTelemetry to_wire(const physics::Telemetry& t, std::uint32_t lost, double ticks_per_second) {
  wire::ArenaTelemetry m;
  m.tick = t.tick;
  m.time = t.time;
  m.inside = t.inside;
  m.waiting = t.waiting;
  m.retreating = t.retreating;
  m.departed = t.departed;
  m.lost_agents = lost;
  m.true_density = t.true_density;
  m.deliveries = t.deliveries;
  m.ticks_per_second = ticks_per_second;
  return m;
}

}  // namespace

RunOutcome run_in_process(const Plan& plan, std::uint64_t seed, const std::string& dir) {
  using Clock = std::chrono::steady_clock;
  const auto launch_start = Clock::now();
  auto s = scenario::load(plan.options.scenario_path, overrides_for_seed(plan, seed));
  s.dds.vendor = scenario::Vendor::inmemory;  // what scenario.yaml in the run directory records

  auto bus = transport::make_inmemory_bus();  // a private "domain" for this run only
  auto participant = [&](const std::string& name, const std::string& user_data) {
    transport::ParticipantOptions o;
    o.domain_id = s.dds.domain;
    o.name = name;
    o.user_data = user_data;
    return transport::make_inmemory_transport(bus, o);
  };

  arena::RunRecorder recorder(dir, s);
  auto arena_transport = participant("retreat-arena", "retreat:arena");
  arena::ArenaNode arena(s, *arena_transport, &recorder);

  std::map<std::uint32_t, InProcessAgent> agents;
  std::set<std::uint32_t> served;  // robots that have had an agent (ids only grow)
  const auto start_agents = [&] {
    for (const auto& f : arena.world().frames()) {
      if (f.phase == physics::Phase::departed || !served.insert(f.id).second) continue;
      InProcessAgent a;
      a.transport = participant("retreat-agent/robot_" + std::to_string(f.id), agent::agent_user_data(f.id));
      a.node = std::make_unique<agent::AgentNode>(s, f.id, *a.transport);
      agents.emplace(f.id, std::move(a));
    }
  };
  start_agents();
  const auto keep_going = [] { return stop_signal.load() == 0; };
  arena.wait_for_agents(std::chrono::seconds(1), keep_going);  // in memory: matched at once

  ProgressLine progress(s.name + " seed " + std::to_string(seed) + " in-process", s.run.duration);
  const auto start = Clock::now();
  while (keep_going()) {
    arena.publish_tick();
    for (auto& [id, a] : agents) a.node->spin_once(std::chrono::nanoseconds(0));
    arena.collect_available();
    if (!arena.all_answered()) {
      // The in-memory transport delivers synchronously: every live agent has answered.
      throw std::logic_error("in-process: an agent did not answer tick " + std::to_string(arena.tick()));
    }
    if (arena.finished()) break;
    arena.step();
    start_agents();  // endless queue: robots appear
    std::erase_if(agents, [](const auto& entry) { return entry.second.node->departed(); });
    if (progress.enabled() && (arena.tick() & 255) == 0) {
      const double wall = std::chrono::duration<double>(Clock::now() - start).count();
      progress.show(to_wire(arena.world().telemetry(), arena.agents_lost(),
                            wall > 0 ? static_cast<double>(arena.tick()) / wall : 0.0));
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  arena.finish(wall);
  progress.finish();

  LaunchRecord record;
  record.dds = "inmemory";
  record.mode = "in-process";
  record.agents_started = static_cast<std::uint32_t>(served.size());
  record.wall_seconds = std::chrono::duration<double>(Clock::now() - launch_start).count();
  record.arena_vendor = "inmemory";
  record.agent_vendors["inmemory"] = record.agents_started;
  RunOutcome out;
  out.summary = update_summary(dir, record);
  out.stopped = !keep_going();
  return out;
}

}  // namespace retreat::launch
