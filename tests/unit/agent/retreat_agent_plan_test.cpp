// RetreatAgent::plan, the look-ahead of issue 13's event-driven lockstep: while a robot's input
// stays unchanged (no new onset, no phase change), its agent's coming decisions are already
// determined, and plan() must give exactly the decisions the agent then takes frame by frame,
// for every registered controller and on both worlds' frame clocks, without changing the agent.

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "agent_test_support.hpp"
#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/core/seed.hpp"

namespace retreat::agent {
namespace {

using testing::clock_frame;
using testing::expect_same_state;
using testing::short_window_params;

/// The worlds' frame clocks: kinetic (one 0.03 s tick per frame) and physical (three 0.01 s
/// physics steps per frame).
constexpr FrameClock kinetic_clock{1, 0.03};
constexpr FrameClock physical_clock{3, 0.01};


/// Outcomes seen over a controller's runs: the test is only meaningful if plans both ended in a
/// retreat and reached their horizon, and if some were voided by an onset.
struct Seen {
  int retreat_planned = 0;
  int stayed_through = 0;
  int voided = 0;
};

/// One run of robot 0: a random stretch of waiting, then inside with onset rates that change in
/// stretches; at random frames the agent plans (a random horizon), and the run then either
/// follows the plan with onset-free frames, checking every frame against it, or voids it with an
/// onset at a random covered tick. A second agent with the same seed gets the same frames and
/// never plans: both must be in the same state after every frame.
void run_with_plans(const std::string& controller, const FrameClock& clock, std::uint64_t seed, Seen& seen) {
  AgentParams params = short_window_params(2.0);  // L = 3 s: decisions from step 100
  params.controller = controller;
  const auto key = seed_for(seed, 0, Stream::agent_decision);
  RetreatAgent planner(0, {}, params, nullptr, key);
  RetreatAgent plain(0, {}, params, nullptr, key);
  Rng rng(seed_for(seed, -1, Stream::world));  // the test's own inputs

  std::int64_t tick = 0;
  const auto feed = [&](const Observation& f) {
    const FrameResult a = planner.on_frame(f);
    const FrameResult b = plain.on_frame(f);
    EXPECT_EQ(a.retreat_now, b.retreat_now) << controller << " seed " << seed << " tick " << f.tick;
    expect_same_state(planner.status(), plain.status());
    return a;
  };

  const auto waiting = static_cast<std::int64_t>(rng.uniform(0.0, 20.0));
  for (; tick < waiting; ++tick) feed(clock_frame(clock, tick, 0, RobotPhase::waiting));

  constexpr double onset_rates[] = {0.0, 0.02, 0.1, 0.3};  // chance of an onset per frame
  double rate = onset_rates[0];
  while (!planner.stopped() && tick < 4000) {
    if (rng.uniform() < 0.01) rate = onset_rates[static_cast<std::size_t>(rng.uniform(0.0, 4.0))];
    if (tick > waiting + 10 && rng.uniform() < 0.03) {
      const auto horizon = 1 + static_cast<std::int64_t>(rng.uniform(0.0, 400.0));
      const Plan plan = planner.plan(clock, horizon);
      ASSERT_EQ(plan.through_tick, plan.retreat_tick.value_or(tick - 1 + horizon))
          << "a plan covers ticks last+1 .. last+horizon, or up to its retreat";
      const bool void_it = rng.uniform() < 0.3;
      const std::int64_t onset_at = tick + static_cast<std::int64_t>(rng.uniform(0.0, static_cast<double>(horizon)));
      bool voided = false;
      for (; tick <= plan.through_tick; ++tick) {
        if (void_it && tick == onset_at) {
          voided = true;
          break;
        }
        const FrameResult r = feed(clock_frame(clock, tick, 0));
        const bool retreat_here = plan.retreat_tick == tick;
        ASSERT_EQ(r.retreat_now, retreat_here) << controller << " seed " << seed << " tick " << tick;
        if (tick == plan.through_tick) (retreat_here ? seen.retreat_planned : seen.stayed_through)++;
      }
      if (voided) {
        // An onset: the plan is void from this tick on; the frame is handled as any other.
        ++seen.voided;
        feed(clock_frame(clock, tick, 1));
        ++tick;
      }
      continue;
    }
    feed(clock_frame(clock, tick, rng.uniform() < rate ? 1 : 0));
    ++tick;
  }
}

class PlanPerController : public ::testing::TestWithParam<std::string> {};

TEST_P(PlanPerController, GivesExactlyTheDecisionsTakenFrameByFrameAndChangesNothing) {
  Seen seen;
  for (const FrameClock& clock : {kinetic_clock, physical_clock}) {
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
      run_with_plans(GetParam(), clock, seed, seen);
      if (HasFatalFailure()) return;
    }
  }
  // Every kind of plan happened (fixed seeds: these counts are the same on every run).
  EXPECT_GT(seen.retreat_planned, 0);
  EXPECT_GT(seen.stayed_through, 0);
  EXPECT_GT(seen.voided, 0);
}

INSTANTIATE_TEST_SUITE_P(Registered, PlanPerController, ::testing::ValuesIn(controller_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string name = p.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

TEST(RetreatAgentPlan, AWaitingOrStoppedAgentStaysThroughTheHorizon) {
  RetreatAgent agent(0, {}, short_window_params(50.0));
  agent.on_frame(clock_frame(kinetic_clock, 0, 0, RobotPhase::waiting));
  const Plan waiting = agent.plan(kinetic_clock, 1000);
  EXPECT_EQ(waiting.through_tick, 1000);
  EXPECT_FALSE(waiting.retreat_tick);
  agent.on_frame(clock_frame(kinetic_clock, 1, 0, RobotPhase::departed));
  const Plan departed = agent.plan(kinetic_clock, 5);
  EXPECT_EQ(departed.through_tick, 6);
  EXPECT_FALSE(departed.retreat_tick);
}

TEST(RetreatAgentPlan, ACertainRetreatIsPlannedAtItsFirstDecisionStep) {
  // p = 1 from 0.3 s inside: entry at tick 2 (kinetic clock), first coin at step 10, tick 12.
  RetreatAgent agent(0, {}, short_window_params(), std::make_unique<testing::FixedProbabilityFrom>(1.0, 0.3));
  agent.on_frame(clock_frame(kinetic_clock, 0, 0, RobotPhase::waiting));
  agent.on_frame(clock_frame(kinetic_clock, 1, 0, RobotPhase::waiting));
  agent.on_frame(clock_frame(kinetic_clock, 2, 0));
  const Plan plan = agent.plan(kinetic_clock, 100);
  EXPECT_EQ(plan.retreat_tick, 12);
  EXPECT_EQ(plan.through_tick, 12);
  EXPECT_FALSE(agent.retreating()) << "the look-ahead ran on a copy";
  EXPECT_EQ(agent.status().steps, 0u);
}

TEST(RetreatAgentPlan, RefusesToPlanWithoutAFrameABadHorizonOrAClockThatGoesBack) {
  RetreatAgent agent(0, {}, short_window_params());
  EXPECT_THROW(agent.plan(kinetic_clock, 10), std::logic_error);
  agent.on_frame(clock_frame(kinetic_clock, 100, 0));  // t = 3 s
  EXPECT_THROW(agent.plan(kinetic_clock, 0), std::invalid_argument);
  EXPECT_THROW(agent.plan({0, 0.03}, 10), std::invalid_argument);
  EXPECT_THROW(agent.plan({1, -0.03}, 10), std::invalid_argument);
  try {
    agent.plan({1, 0.001}, 10);  // tick 101 at 0.101 s, before the last frame's 3 s
    FAIL() << "a clock that goes back was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tick 101"), std::string::npos) << e.what();
  }
}

TEST(RetreatAgentCopy, GoesOnAloneWithItsOwnControllerState) {
  // influx-aware keeps its own record of past steps: a copy must not share it. No onsets (λ̂ = 0,
  // below λ*) keep the original deciding without leaving.
  AgentParams params = short_window_params(5.0);
  params.controller = "influx-aware";
  RetreatAgent original(0, {}, params, nullptr, 7);
  for (std::int64_t tick = 0; tick < 150; ++tick) original.on_frame(clock_frame(kinetic_clock, tick, 0));
  ASSERT_TRUE(original.status().deciding);
  RetreatAgent copy(original);
  RetreatAgent reference(original);
  std::int64_t tick = 150;
  for (; tick < 1000 && !copy.stopped(); ++tick) copy.on_frame(clock_frame(kinetic_clock, tick, 1));
  EXPECT_GT(copy.status().steps, original.status().steps);
  expect_same_state(original.status(), reference.status());
  // Had the copy stepped the original's controller, the two would now part.
  for (std::int64_t t = 150; t < 600 && !original.stopped(); ++t) {
    const Observation f = clock_frame(kinetic_clock, t, t % 50 == 0);
    EXPECT_EQ(original.on_frame(f).retreat_now, reference.on_frame(f).retreat_now);
    expect_same_state(original.status(), reference.status());
  }
}

}  // namespace
}  // namespace retreat::agent
