#include "retreat/launch/in_memory_run.hpp"

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/agent/agent_node.hpp"
#include "retreat/transport/inmemory.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::launch {
namespace {

struct InProcessAgent {
  std::unique_ptr<transport::Transport> transport;
  std::unique_ptr<agent::AgentNode> node;
};

}  // namespace

InMemoryRun run_in_memory(const scenario::Scenario& s, arena::RunRecorder* recorder,
                          const std::function<bool()>& keep_going,
                          const std::function<void(const arena::ArenaNode&, double)>& on_tick) {
  using Clock = std::chrono::steady_clock;
  // A private "domain" for this run only, stepped by this thread alone: nothing locks.
  auto bus = transport::make_inmemory_bus(transport::Threading::confined);
  auto participant = [&](const std::string& name, const std::string& user_data) {
    transport::ParticipantOptions o;
    o.domain_id = s.dds.domain;
    o.name = name;
    o.user_data = user_data;
    return transport::make_inmemory_transport(bus, o);
  };

  auto arena_transport = participant("retreat-arena", wire::arena_user_data);
  arena::ArenaNode arena(s, *arena_transport, recorder);
  arena.settle_plans_at_end(false);  // nobody reads the agents' statuses on this private bus

  // By robot id; empty once the robot has departed. Ids only grow and are dense, so the robots
  // without an agent yet are the ids from agents.size() on.
  std::vector<InProcessAgent> agents;
  std::uint32_t started = 0;
  const auto start_agents = [&] {
    const auto& world = arena.world();
    for (auto id = static_cast<std::uint32_t>(agents.size()); id < world.robot_count(); ++id) {
      auto& a = agents.emplace_back();
      if (world.robot_stats(id).phase == physics::Phase::departed) continue;
      a.transport = participant("retreat-agent/robot_" + std::to_string(id), agent::agent_user_data(id));
      a.node = std::make_unique<agent::AgentNode>(s, id, *a.transport);
      ++started;
    }
  };
  start_agents();
  arena.wait_for_agents(std::chrono::seconds(1), keep_going);  // in memory: matched at once

  const auto start = Clock::now();
  while (keep_going()) {
    arena.publish_tick();
    // Only the agents sent a frame have anything to do (with run.plans, the robots whose input
    // changed; otherwise every live one).
    for (const auto id : arena.frames_sent()) {
      if (id < agents.size() && agents[id].node) agents[id].node->spin_once(std::chrono::nanoseconds(0));
    }
    if (!arena.collect_available()) {
      // The in-memory transport delivers synchronously: every live agent has answered.
      throw std::logic_error("in-process: an agent did not answer tick " + std::to_string(arena.tick()));
    }
    if (arena.finished()) break;
    arena.step();
    // An agent departs on its robot's departed frame, so only those sent a frame can have.
    for (const auto id : arena.frames_sent()) {
      if (id >= agents.size()) continue;
      if (auto& a = agents[id]; a.node && a.node->departed()) {
        a.node.reset();  // first: a node must not outlive its transport
        a.transport.reset();
      }
    }
    start_agents();  // endless queue: robots appear
    if (on_tick) on_tick(arena, std::chrono::duration<double>(Clock::now() - start).count());
  }
  InMemoryRun out;
  out.summary = arena.finish(std::chrono::duration<double>(Clock::now() - start).count());
  out.agents_started = started;
  return out;
}

}  // namespace retreat::launch
