#include "retreat/launch/in_memory_run.hpp"

#include <chrono>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "retreat/agent/agent_node.hpp"
#include "retreat/transport/inmemory.hpp"

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
  auto bus = transport::make_inmemory_bus();  // a private "domain" for this run only
  auto participant = [&](const std::string& name, const std::string& user_data) {
    transport::ParticipantOptions o;
    o.domain_id = s.dds.domain;
    o.name = name;
    o.user_data = user_data;
    return transport::make_inmemory_transport(bus, o);
  };

  auto arena_transport = participant("retreat-arena", "retreat:arena");
  arena::ArenaNode arena(s, *arena_transport, recorder);

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
  arena.wait_for_agents(std::chrono::seconds(1), keep_going);  // in memory: matched at once

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
    if (on_tick) on_tick(arena, std::chrono::duration<double>(Clock::now() - start).count());
  }
  InMemoryRun out;
  out.summary = arena.finish(std::chrono::duration<double>(Clock::now() - start).count());
  out.agents_started = static_cast<std::uint32_t>(served.size());
  return out;
}

}  // namespace retreat::launch
