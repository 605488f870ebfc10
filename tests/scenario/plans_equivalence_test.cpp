// Event-driven lockstep (run.plans) gives the per-tick lockstep's trajectory, bit for bit: for
// every shipped scenario (both worlds, both queues) and every registered controller, in one
// process (the arena's and every agent's own code over the in-memory transport), with the default
// plan horizon and with a horizon of 7 ticks (plans end and are renewed all the time). Over real
// DDS processes, each vendor and mixed: tests/integration/launch_runs_test.cpp.
//
// The runs are shortened (150 s) with L = 20 s and K_p = 0.5 so that every controller decides
// and robots retreat within them; the per-tick and the planned run see the same inputs.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "retreat/agent/agent_node.hpp"
#include "retreat/agent/controller_registry.hpp"
#include "retreat/arena/arena_node.hpp"
#include "retreat/launch/in_memory_run.hpp"
#include "retreat/physics/world.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/inmemory.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string scenario;  ///< file name in deploy/scenarios
  std::string controller;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  for (const auto& entry : fs::directory_iterator(RETREAT_SCENARIOS)) {
    if (entry.path().extension() != ".yaml") continue;
    for (const auto& c : agent::controller_names()) out.push_back({entry.path().filename().string(), c});
  }
  return out;
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.scenario << " " << c.controller; }

class PlansEquivalence : public ::testing::TestWithParam<Case> {};

struct Run {
  launch::InMemoryRun result;
  std::uint32_t left = 0;  ///< robots that retreated or departed by the end
};

/// @p c's scenario shortened as the header says, per tick unless @p extra says otherwise (the
/// shipped scenarios set run.plans: true).
scenario::Scenario shortened(const Case& c, const std::vector<std::string>& extra) {
  std::vector<std::string> overrides = {"agent.controller=" + c.controller, "run.duration=150", "agent.L=20",
                                        "agent.K_p=0.5", "run.plans=false"};
  if (c.scenario == "kinetic-1000.yaml") overrides.push_back("arena.robots_inside=200");  // CI time
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return scenario::load(std::string(RETREAT_SCENARIOS) + "/" + c.scenario, overrides);
}

/// A participant named @p name on @p bus, in @p s's domain.
std::unique_ptr<transport::Transport> participant(const std::shared_ptr<transport::InMemoryBus>& bus,
                                                  const scenario::Scenario& s, const std::string& name) {
  transport::ParticipantOptions o;
  o.domain_id = s.dds.domain;
  o.name = name;
  return transport::make_inmemory_transport(bus, o);
}

Run run(const Case& c, const std::vector<std::string>& extra) {
  const auto s = shortened(c, extra);
  Run out;
  out.result = launch::run_in_memory(s, nullptr, [] { return true; }, [&](const arena::ArenaNode& arena, double) {
    const auto t = arena.world().telemetry();
    out.left = t.retreating + t.departed;
  });
  return out;
}

TEST_P(PlansEquivalence, PlansGiveThePerTickTrajectory) {
  const auto per_tick = run(GetParam(), {}).result;
  ASSERT_EQ(per_tick.summary.decisions_planned, 0u);
  for (const char* horizon : {"run.plan_horizon=500", "run.plan_horizon=7"}) {
    const auto planned = run(GetParam(), {"run.plans=true", horizon}).result;
    EXPECT_EQ(planned.summary.trajectory_sha256, per_tick.summary.trajectory_sha256) << horizon;
    EXPECT_EQ(planned.summary.ticks, per_tick.summary.ticks) << horizon;
    EXPECT_EQ(planned.agents_started, per_tick.agents_started) << horizon;
    // The plans did the work: most robot-ticks were decided without a frame.
    EXPECT_GT(planned.summary.decisions_planned, planned.summary.decisions_received) << horizon;
    EXPECT_LT(planned.summary.decisions_received, per_tick.summary.decisions_received) << horizon;
    // Every plan answered a frame the arena was waiting for: none is left over or dropped.
    EXPECT_EQ(planned.summary.decisions_dropped, 0u) << horizon;
  }
}

INSTANTIATE_TEST_SUITE_P(ShippedScenarios, PlansEquivalence, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& test) {
                           std::string name = test.param.scenario.substr(0, test.param.scenario.size() - 5) + "_" +
                                              test.param.controller;
                           for (char& ch : name) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           return name;
                         });

TEST(PlansEquivalence, RobotsRetreatUnderEveryControllerInTheseRuns) {
  // Guards the test above against runs in which nothing is decided: with its overrides,
  // robotarium-2019 (12 robots, twice the optimum) sees robots retreat under every controller.
  for (const auto& c : agent::controller_names()) {
    EXPECT_GT(run({"robotarium-2019.yaml", c}, {"run.plans=true"}).left, 0u) << c;
  }
}

TEST(PlansEquivalence, ANoisySensorsMissedAndFalseOnsetsVoidPlansAsRealOnesDo) {
  // The arena covers a tick only when the robot's sensor reports no onset: a false onset voids
  // a plan, a missed one leaves it in force, exactly as the agent would have seen the frame.
  for (const auto& c : agent::controller_names()) {
    const Case noisy{"robotarium-2019.yaml", c};
    const std::vector<std::string> noise = {"arena.missed_onsets=0.3", "arena.false_onsets=0.05"};
    auto planned_overrides = noise;
    planned_overrides.push_back("run.plans=true");
    const auto per_tick = run(noisy, noise).result;
    const auto planned = run(noisy, planned_overrides).result;
    EXPECT_EQ(planned.summary.trajectory_sha256, per_tick.summary.trajectory_sha256) << c;
    EXPECT_GT(planned.summary.decisions_planned, 0u) << c;
  }
}

/// One robot alone (no encounter, so its first plan covers the run up to its last tick, which is
/// sent to every robot) in event-driven lockstep,
/// stepped like run_in_memory; with `extra`, a repeated answer to its first frame is written on
/// its plan topic once the last tick's answers are read, so that only the end of the run reads it.
arena::RunSummary lone_robot_run(bool extra) {
  const auto s = scenario::load(std::string(RETREAT_SCENARIOS) + "/kinetic-1000.yaml",
                                {"arena.robots_inside=1", "run.duration=1.5", "run.plans=true"});
  auto bus = transport::make_inmemory_bus(transport::Threading::confined);
  auto arena_transport = participant(bus, s, "arena");
  arena::ArenaNode arena(s, *arena_transport, nullptr);
  auto agent_transport = participant(bus, s, "agent");
  agent::AgentNode agent(s, 0, *agent_transport);
  auto stray_transport = participant(bus, s, "stray");
  auto stray = stray_transport->create_writer<wire::Decision>(
      {wire::plan_topic(s.dds.prefix, 0), transport::QosIntent::answers()});
  EXPECT_EQ(arena.wait_for_agents(std::chrono::seconds(1), [] { return true; }), 1u);
  std::size_t frames = 0;
  for (;;) {
    arena.publish_tick();
    frames += arena.frames_sent().size();
    if (!arena.frames_sent().empty()) agent.spin_once(std::chrono::nanoseconds(0));
    EXPECT_TRUE(arena.collect_available()) << "tick " << arena.tick();
    if (extra && arena.finished()) stray.write({0, 500, 0.0, false});  // tick 0's frame, again
    if (arena.finished()) break;
    arena.step();
  }
  // The robot's first plan covers the whole run; the run's last tick is sent to every robot.
  EXPECT_EQ(frames, 2u);
  return arena.finish(1.0);
}

TEST(PlansEquivalence, APlanLeftUnreadAnswersASettledFrameAndIsCountedDroppedAtTheEnd) {
  // The arena reads only the plan readers of robots it sent a frame: what else arrives is
  // counted when the run ends, not lost from the summary.
  const auto clean = lone_robot_run(false);
  EXPECT_EQ(clean.decisions_dropped, 0u);
  EXPECT_EQ(clean.decisions_received, 2u);  // the first frame's and the last tick's
  const auto repeated = lone_robot_run(true);
  EXPECT_EQ(repeated.decisions_dropped, 1u);
  EXPECT_EQ(repeated.decisions_received, 2u);
  EXPECT_EQ(repeated.trajectory_sha256, clean.trajectory_sha256);
}

/// Every agent status published in a run of @p c stepped like run_in_memory, robot by robot in
/// publication order, as a bridge reading the status topic would see them; and the agents' count
/// of covered frames.
struct StatusRun {
  std::map<std::uint32_t, std::vector<wire::AgentStatus>> statuses;
  std::uint64_t covered = 0;
  std::string trajectory_sha256;
};

StatusRun status_run(const Case& c, const std::vector<std::string>& extra) {
  std::vector<std::string> overrides = {"run.status_period=0.5"};
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  const auto s = shortened(c, overrides);
  auto bus = transport::make_inmemory_bus(transport::Threading::confined);
  auto listener = participant(bus, s, "listener");
  // Keep all (the topic's writers keep the last status per robot): every status, in order.
  auto statuses = listener->create_reader<wire::AgentStatus>(
      {wire::agent_status_topic(s.dds.prefix), transport::QosIntent::control()});
  auto arena_transport = participant(bus, s, "arena");
  arena::ArenaNode arena(s, *arena_transport, nullptr);
  struct Agent {
    std::unique_ptr<transport::Transport> transport;
    std::unique_ptr<agent::AgentNode> node;
  };
  std::vector<Agent> agents;
  StatusRun out;
  const auto retire = [&](Agent& a) {
    out.covered += a.node->counters().frames_covered;
    a.node.reset();
    a.transport.reset();
  };
  const auto start_agents = [&] {
    for (auto id = static_cast<std::uint32_t>(agents.size()); id < arena.world().robot_count(); ++id) {
      auto& a = agents.emplace_back();
      a.transport = participant(bus, s, "agent_" + std::to_string(id));
      a.node = std::make_unique<agent::AgentNode>(s, id, *a.transport);
    }
  };
  const auto read_statuses = [&] {
    std::vector<wire::AgentStatus> taken;
    statuses.take(taken);
    for (const auto& st : taken) out.statuses[st.robot_id].push_back(st);
  };
  start_agents();
  arena.wait_for_agents(std::chrono::seconds(1), [] { return true; });
  for (;;) {
    arena.publish_tick();
    for (const auto id : arena.frames_sent()) {
      if (id < agents.size() && agents[id].node) agents[id].node->spin_once(std::chrono::nanoseconds(0));
    }
    EXPECT_TRUE(arena.collect_available()) << "tick " << arena.tick();
    read_statuses();
    if (arena.finished()) break;
    arena.step();
    for (const auto id : arena.frames_sent()) {
      if (id < agents.size() && agents[id].node && agents[id].node->departed()) retire(agents[id]);
    }
    start_agents();
  }
  for (auto& a : agents) {
    if (a.node) retire(a);
  }
  read_statuses();
  out.trajectory_sha256 = arena.finish(1.0).trajectory_sha256;
  return out;
}

TEST(PlansEquivalence, AgentsPublishThePerTickStatusesWhilePlansAreInForce) {
  // What the bridge shows of each agent (its estimate, rate and state at every status period)
  // must not depend on the lockstep: the frames a plan covers publish the statuses the per-tick
  // agent publishes, when the agent acts on them at its next frame; the run's last tick is sent
  // to every robot, so that no plan in force leaves its ticks' statuses unpublished at the end.
  for (const Case& c : {Case{"robotarium-2019.yaml", "paper"}, Case{"robotarium-2019.yaml", "confident-proportional"},
                        Case{"steady-influx.yaml", "influx-matching"}}) {
    const auto per_tick = status_run(c, {});
    ASSERT_FALSE(per_tick.statuses.empty()) << c.scenario;
    EXPECT_EQ(per_tick.covered, 0u);
    for (const std::int64_t horizon_ticks : {500, 7}) {
      const std::string horizon = "run.plan_horizon=" + std::to_string(horizon_ticks);
      const auto planned = status_run(c, {"run.plans=true", horizon});
      EXPECT_EQ(planned.trajectory_sha256, per_tick.trajectory_sha256) << c.scenario << " " << horizon;
      EXPECT_GT(planned.covered, 0u) << c.scenario << " " << horizon;
      ASSERT_EQ(planned.statuses.size(), per_tick.statuses.size()) << c.scenario << " " << horizon;
      std::size_t compared = 0;
      for (const auto& [robot, expected] : per_tick.statuses) {
        const auto it = planned.statuses.find(robot);
        ASSERT_NE(it, planned.statuses.end()) << c.scenario << " robot " << robot;
        ASSERT_EQ(it->second.size(), expected.size()) << c.scenario << " " << horizon << " robot " << robot;
        compared += expected.size();
        for (std::size_t i = 0; i < expected.size(); ++i) {
          ASSERT_EQ(it->second[i], expected[i])
              << c.scenario << " " << horizon << " robot " << robot << " status " << i << " (tick "
              << expected[i].tick << ")";
        }
      }
      EXPECT_GT(compared, 100u) << c.scenario << " " << horizon;
    }
  }
}

TEST(FrameClock, EveryWorldsFramesAreOnTheScenariosFrameClockBitForBit) {
  // What a planning agent assumes of the frames it is not sent (scenario::frame_clock).
  for (const char* file : {"robotarium-2019.yaml", "kinetic-1000.yaml", "validation-encounters.yaml"}) {
    const auto s = scenario::load(std::string(RETREAT_SCENARIOS) + "/" + file, {"arena.robots_inside=20"});
    const auto clock = scenario::frame_clock(s);
    auto world = physics::make_world(s.arena);
    std::size_t checked = 0;
    for (int tick = 0; tick < 5000; ++tick) {
      for (const auto& f : world->frames()) {
        ASSERT_EQ(f.time, clock.time(f.tick)) << file << " robot " << f.id << " tick " << f.tick;
        ++checked;
      }
      world->step_tick();
    }
    EXPECT_GE(checked, 5000u * 20u) << file;
  }
}


TEST(AgentNodeReaders, ARecordersReaderIsNotCountedAsAnArenaIncarnation) {
  // An agent tells a new arena incarnation from a recorder by the reader's participant, looked
  // up alone (Transport::participant): in a swarm of 10⁵ in one process, listing every
  // participant for each agent made the run's first second quadratic in N.
  const auto s = scenario::load(std::string(RETREAT_SCENARIOS) + "/kinetic-1000.yaml", {"arena.robots_inside=1"});
  auto bus = transport::make_inmemory_bus(transport::Threading::confined);
  auto agent_transport = participant(bus, s, "agent");
  agent::AgentNode agent(s, 0, *agent_transport);
  const auto reader_on = [&](transport::Transport& t) {
    return t.create_reader<wire::Decision>({wire::decision_topic(s.dds.prefix, 0), transport::QosIntent::answers()});
  };
  transport::ParticipantOptions recording;
  recording.domain_id = s.dds.domain;
  recording.name = "retreat-record";
  recording.user_data = wire::recorder_user_data;
  auto recorder_transport = transport::make_inmemory_transport(bus, recording);
  auto recorder_reader = reader_on(*recorder_transport);
  auto first_transport = participant(bus, s, "arena");
  auto first_reader = reader_on(*first_transport);
  // Readers are looked at once a second of wall time (AgentNode's reader_check_period).
  const auto spin_until = [&](std::uint32_t incarnations) {
    const auto deadline = std::chrono::steady_clock::now() + testing::hang_ceiling;
    while (agent.counters().arena_incarnations < incarnations && std::chrono::steady_clock::now() < deadline) {
      agent.spin_once(std::chrono::milliseconds(5));
    }
  };
  spin_until(1);
  EXPECT_EQ(agent.counters().arena_incarnations, 1u);
  auto second_transport = participant(bus, s, "arena-again");
  auto second_reader = reader_on(*second_transport);
  spin_until(2);
  EXPECT_EQ(agent.counters().arena_incarnations, 2u);
}

}  // namespace
}  // namespace retreat
