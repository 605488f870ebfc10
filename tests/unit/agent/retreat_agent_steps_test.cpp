#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>

#include "agent_test_support.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

using testing::FixedProbability;
using testing::frame_at;
using testing::short_window_params;

TEST(RetreatAgent, ConstructsWithAllDefaults) {
  const RetreatAgent agent;
  EXPECT_EQ(agent.robot_id(), 0u);
  EXPECT_EQ(agent.controller().name(), "paper");
  EXPECT_FALSE(agent.retreating());
  EXPECT_FALSE(agent.status().tick.has_value());
}

TEST(RetreatAgent, TakesExactlyOneStepPerFrameInLockstep) {
  RetreatAgent agent;
  const double dt = agent.agent_params().dt;
  for (std::int64_t tick = 0; tick < 5; ++tick) {
    agent.on_frame(frame_at(tick, dt, 0, RobotPhase::waiting));
  }
  // Entry at tick 5 (t = 0.15): t_entry + k·dt and tick·dt differ by rounding only.
  for (std::int64_t tick = 5; tick < 5000; ++tick) {
    agent.on_frame(frame_at(tick, dt));
    ASSERT_EQ(agent.status().steps, static_cast<std::uint64_t>(tick - 5)) << "tick " << tick;
  }
  EXPECT_EQ(agent.status().entry_time, 5 * dt);
}

TEST(RetreatAgent, TakesNoDecisionBeforeItHasBeenInsideForL) {
  // Experiment parameters: L = 90 s, dt = 0.03 s, entry at t = 0: the first coin is at step
  // 3000 (t_k − t_entry = L exactly), never at step 2999.
  RetreatAgent agent;
  const double dt = agent.agent_params().dt;
  for (std::int64_t tick = 0; tick <= 2999; ++tick) {
    agent.on_frame(frame_at(tick, dt, tick % 100 == 1 ? 1 : 0));
  }
  EXPECT_EQ(agent.status().steps, 2999u);
  EXPECT_EQ(agent.status().decision_steps, 0u);
  EXPECT_FALSE(agent.status().deciding);
  agent.on_frame(frame_at(3000, dt));
  EXPECT_EQ(agent.status().decision_steps, 1u);
  EXPECT_EQ(agent.status().onsets_in_window, 30u);  // ticks 1, 101, ..., 2901
}

TEST(RetreatAgent, AsksAControllerThatDecidesEarlierFromItsOwnFirstDecisionTime) {
  // L = 90 s; the controller decides from 1.5 s inside: entry at tick 5, first coin at step 50
  // (t_k − t_entry = 1.5 s), with the onsets counted since entry in the window.
  AgentParams params;
  RetreatAgent agent(0, {}, params, std::make_unique<testing::FixedProbabilityFrom>(0.0, 1.5));
  for (std::int64_t tick = 0; tick < 5; ++tick) {
    agent.on_frame(frame_at(tick, params.dt, 1, RobotPhase::waiting));  // not counted: outside
  }
  for (std::int64_t tick = 5; tick < 5 + 49; ++tick) {
    agent.on_frame(frame_at(tick, params.dt, tick == 6 ? 2 : 0));
  }
  EXPECT_EQ(agent.status().steps, 48u);
  EXPECT_EQ(agent.status().decision_steps, 0u);
  agent.on_frame(frame_at(5 + 49, params.dt));
  agent.on_frame(frame_at(5 + 50, params.dt));
  EXPECT_EQ(agent.status().steps, 50u);
  EXPECT_EQ(agent.status().decision_steps, 1u);
  EXPECT_EQ(agent.status().onsets_in_window, 2u);
}

TEST(RetreatAgent, RefusesAControllerWhoseFirstDecisionTimeIsNegativeOrNotFinite) {
  for (const double first : {-1.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(RetreatAgent(0, {}, {}, std::make_unique<testing::FixedProbabilityFrom>(0.0, first)),
                 std::invalid_argument)
        << first;
  }
}

TEST(RetreatAgent, RetreatsAtExactlyTheFirstDecisionTickWhenEpsilonDtIsAtLeastOne) {
  // K_p = 100 and 100 onsets in the first window: λ̂ = 100/(cL) = 21.8, ε(λ̂) = 93 /s,
  // ε·dt = 2.8 >= 1, so the coin must come up "retreat" at the first decision, for any seed.
  AgentParams params;
  params.K_p = 100.0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    RetreatAgent agent(0, {}, params, nullptr, seed_for(seed, 0, Stream::agent_decision));
    for (std::int64_t tick = 0; tick < 3000; ++tick) {
      ASSERT_FALSE(agent.on_frame(frame_at(tick, params.dt, tick == 1 ? 100 : 0)).retreating);
    }
    const FrameResult result = agent.on_frame(frame_at(3000, params.dt));
    EXPECT_TRUE(result.retreat_now);
    EXPECT_TRUE(result.retreating);
    EXPECT_GE(agent.status().epsilon * params.dt, 1.0);
    EXPECT_EQ(agent.status().decision_time, 3000 * params.dt);
  }
}

TEST(RetreatAgent, NeverRetreatsWhileTheEstimateIsAtOrBelowLambdaStar) {
  // One onset every 600 ticks (18 s): any closed 90 s window holds at most 6, so
  // λ̂ <= 6/(cL) = 1.309 < λ* = 1.5076 and ε = 0 at every step, even with a huge gain.
  AgentParams params;
  params.K_p = 100.0;
  RetreatAgent agent(0, {}, params, nullptr, 42);
  for (std::int64_t tick = 0; tick <= 30000; ++tick) {
    ASSERT_FALSE(agent.on_frame(frame_at(tick, params.dt, tick % 600 == 0 ? 1 : 0)).retreating);
    if (agent.status().decision_steps > 0) {
      ASSERT_LE(agent.status().lambda_hat, model::lambda_star(agent.model_params()));
      ASSERT_EQ(agent.status().epsilon, 0.0);
    }
  }
  EXPECT_EQ(agent.status().decision_steps, 27001u);
}

TEST(RetreatAgent, StopsDecidingAfterItDecidedToRetreat) {
  AgentParams params = short_window_params();
  RetreatAgent agent(0, {}, params, std::make_unique<FixedProbability>(1.0), 1);
  std::int64_t tick = 0;
  while (!agent.on_frame(frame_at(tick, params.dt)).retreat_now) {
    ++tick;
  }
  EXPECT_EQ(tick, 100);
  const AgentSnapshot at_decision = agent.status();
  // The arena has not reacted yet: more `inside` frames arrive.
  for (++tick; tick < 400; ++tick) {
    const FrameResult result = agent.on_frame(frame_at(tick, params.dt, 5));
    EXPECT_FALSE(result.retreat_now);
    EXPECT_TRUE(result.retreating);
  }
  EXPECT_EQ(agent.status().steps, at_decision.steps);
  EXPECT_EQ(agent.status().decision_steps, at_decision.decision_steps);
  EXPECT_TRUE(agent.status().stopped);
  EXPECT_FALSE(agent.status().deciding);
}

TEST(RetreatAgent, StopsDecidingOnceThePhaseIsRetreatingOrDeparted) {
  for (const RobotPhase phase : {RobotPhase::retreating, RobotPhase::departed}) {
    AgentParams params = short_window_params();
    RetreatAgent agent(0, {}, params, std::make_unique<FixedProbability>(0.0), 1);
    for (std::int64_t tick = 0; tick <= 150; ++tick) {
      agent.on_frame(frame_at(tick, params.dt));
    }
    EXPECT_EQ(agent.status().decision_steps, 51u);
    agent.on_frame(frame_at(151, params.dt, 0, phase));
    for (std::int64_t tick = 152; tick < 300; ++tick) {
      agent.on_frame(frame_at(tick, params.dt));
    }
    EXPECT_EQ(agent.status().steps, 150u) << to_string(phase);
    EXPECT_EQ(agent.status().decision_steps, 51u);
    EXPECT_FALSE(agent.retreating());
    EXPECT_TRUE(agent.stopped());
  }
}

TEST(RetreatAgent, CountsOnsetsOnlyWhileInside) {
  AgentParams params = short_window_params();
  RetreatAgent agent(0, {}, params, std::make_unique<FixedProbability>(0.0), 1);
  for (std::int64_t tick = 0; tick < 50; ++tick) {
    agent.on_frame(frame_at(tick, params.dt, 3, RobotPhase::waiting));
  }
  for (std::int64_t tick = 50; tick <= 150; ++tick) {
    agent.on_frame(frame_at(tick, params.dt, tick == 60 ? 2 : 0));
  }
  EXPECT_EQ(agent.status().entry_time, 50 * params.dt);
  EXPECT_EQ(agent.status().decision_steps, 1u);
  EXPECT_EQ(agent.status().onsets_in_window, 2u);
}

TEST(RetreatAgent, TakesEveryMissedStepWhenFramesArriveInBursts) {
  // Lockstep: a frame every dt. Bursty: a frame every 10·dt. Onsets fall on every 10th tick
  // only, so both agents see the same onset times; with the same seed they must take the same
  // steps, flip the same coins and decide at the same step time.
  const AgentParams params = short_window_params(0.5);
  const std::uint64_t seed = seed_for(7, 3, Stream::agent_decision);
  RetreatAgent lockstep(3, {}, params, nullptr, seed);
  RetreatAgent bursty(3, {}, params, nullptr, seed);
  for (std::int64_t tick = 0; tick <= 5000; ++tick) {
    const std::uint32_t onsets = tick % 10 == 0 ? 2 : 0;
    lockstep.on_frame(frame_at(tick, params.dt, onsets, RobotPhase::inside, 3));
    if (tick % 10 == 0) {
      bursty.on_frame(frame_at(tick, params.dt, onsets, RobotPhase::inside, 3));
      ASSERT_EQ(bursty.status().steps, lockstep.status().steps) << "tick " << tick;
      ASSERT_EQ(bursty.status().decision_steps, lockstep.status().decision_steps);
      ASSERT_EQ(bursty.retreating(), lockstep.retreating()) << "tick " << tick;
    }
  }
  ASSERT_TRUE(lockstep.retreating()) << "the comparison should cover a decision";
  EXPECT_EQ(bursty.status().decision_time, lockstep.status().decision_time);
  EXPECT_EQ(bursty.status().lambda_hat, lockstep.status().lambda_hat);
}

TEST(RetreatAgent, TakesOneStepPerElapsedDtWhateverTheFrameTimes) {
  // Frames at irregular times (gaps of 0 to 5 dt, repeated times allowed): after each frame,
  // steps = floor((t − t_entry)/dt) (up to the 1e-9·dt tolerance).
  const AgentParams params = short_window_params();
  RetreatAgent agent(0, {}, params, std::make_unique<FixedProbability>(0.0), 1);
  retreat::Rng generator(99);
  double time = 1.234;
  for (std::int64_t tick = 0; tick < 5000; ++tick) {
    Observation frame = frame_at(tick, params.dt);
    frame.time = time;
    agent.on_frame(frame);
    const double expected = std::floor((time - 1.234) / params.dt + 1e-9);
    ASSERT_EQ(static_cast<double>(agent.status().steps), expected) << "time " << time;
    time += tick % 7 == 0 ? 0.0 : generator.uniform(0.0, 5.0 * params.dt);
  }
}

TEST(RetreatAgent, ClampsTheControllersProbabilityToZeroAndOne) {
  const AgentParams params = short_window_params();
  RetreatAgent never(0, {}, params, std::make_unique<FixedProbability>(-5.0), 1);
  RetreatAgent always(0, {}, params, std::make_unique<FixedProbability>(7.0), 1);
  for (std::int64_t tick = 0; tick <= 1000; ++tick) {
    never.on_frame(frame_at(tick, params.dt));
    always.on_frame(frame_at(tick, params.dt));
  }
  EXPECT_FALSE(never.retreating());
  EXPECT_EQ(never.status().decision_steps, 901u);
  EXPECT_TRUE(always.retreating());
  EXPECT_EQ(always.status().decision_steps, 1u);
}

TEST(RetreatAgent, RefusesANanProbabilityFromItsController) {
  const AgentParams params = short_window_params();
  RetreatAgent agent(0, {}, params, std::make_unique<FixedProbability>(std::nan("")), 1);
  for (std::int64_t tick = 0; tick < 100; ++tick) {
    agent.on_frame(frame_at(tick, params.dt));
  }
  EXPECT_THROW(agent.on_frame(frame_at(100, params.dt)), std::logic_error);
}

}  // namespace
}  // namespace retreat::agent
