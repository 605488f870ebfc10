#include <gtest/gtest.h>

#include <cstdint>
#include <limits>

#include "agent_test_support.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/seed.hpp"

namespace retreat::agent {
namespace {

using testing::expect_same_state;
using testing::frame_at;
using testing::short_window_params;

constexpr std::uint32_t robot = 4;

/// A frame for this test's robot with many onsets and a phase that would stop the agent:
/// acting on it in any way would show.
Observation tempting(std::int64_t tick, double time) {
  Observation frame = frame_at(tick, 1.0, 50, RobotPhase::departed, robot);
  frame.time = time;
  return frame;
}

TEST(RetreatAgent, DropsAndCountsBadFramesWithoutActingOnThem) {
  const AgentParams params = short_window_params(0.5);
  const double dt = params.dt;
  const std::uint64_t seed = seed_for(11, robot, Stream::agent_decision);
  RetreatAgent clean(robot, {}, params, nullptr, seed);
  RetreatAgent noisy(robot, {}, params, nullptr, seed);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();

  FrameCounts injected;
  const auto inject = [&](const Observation& frame, FrameVerdict expected) {
    EXPECT_EQ(noisy.on_frame(frame).verdict, expected) << "tick " << frame.tick;
    injected.count(expected);
  };
  for (std::int64_t tick = 0; tick <= 3000; ++tick) {
    const double time = static_cast<double>(tick) * dt;
    if (tick % 5 == 0) {
      Observation other = tempting(tick, time);
      other.robot_id = robot + 1;
      inject(other, FrameVerdict::wrong_robot);
    }
    if (tick % 7 == 3) {
      inject(tempting(tick, nan), FrameVerdict::bad_time);
      inject(tempting(tick, inf), FrameVerdict::bad_time);
      inject(tempting(tick, -1.0), FrameVerdict::bad_time);
    }
    if (tick % 11 == 4 && tick > 10) {
      inject(tempting(tick, time - 5.0 * dt), FrameVerdict::bad_time);  // time backwards
    }
    const std::uint32_t onsets = tick % 10 == 0 ? 2 : 0;
    const FrameResult expected =
        clean.on_frame(frame_at(tick, dt, onsets, RobotPhase::inside, robot));
    const FrameResult got = noisy.on_frame(frame_at(tick, dt, onsets, RobotPhase::inside, robot));
    ASSERT_EQ(got.verdict, FrameVerdict::accepted);
    ASSERT_EQ(got.retreat_now, expected.retreat_now) << "tick " << tick;
    ASSERT_EQ(got.retreating, expected.retreating) << "tick " << tick;
    if (tick % 3 == 1) {
      inject(tempting(tick, time), FrameVerdict::duplicate_tick);
    }
    if (tick % 13 == 2 && tick > 0) {
      inject(tempting(tick - 1, time), FrameVerdict::stale_tick);
    }
    expect_same_state(noisy.status(), clean.status());
  }
  ASSERT_TRUE(clean.retreating()) << "the comparison should cover a decision";
  EXPECT_EQ(noisy.frames()[FrameVerdict::accepted], 3001u);
  for (const FrameVerdict verdict : {FrameVerdict::wrong_robot, FrameVerdict::stale_tick,
                                     FrameVerdict::duplicate_tick, FrameVerdict::bad_time}) {
    EXPECT_GT(injected[verdict], 0u) << to_string(verdict);
    EXPECT_EQ(noisy.frames()[verdict], injected[verdict]) << to_string(verdict);
  }
  EXPECT_EQ(noisy.frames().dropped(), injected.dropped());
  EXPECT_EQ(clean.frames().dropped(), 0u);
}

TEST(RetreatAgent, AcceptsAnyFirstTickAndRepeatedTimesWithIncreasingTicks) {
  RetreatAgent agent;
  EXPECT_EQ(agent.on_frame(frame_at(1000, 0.03)).verdict, FrameVerdict::accepted);
  Observation same_time = frame_at(1001, 0.03);
  same_time.time = 1000 * 0.03;
  EXPECT_EQ(agent.on_frame(same_time).verdict, FrameVerdict::accepted);
  EXPECT_EQ(agent.on_frame(frame_at(1003, 0.03)).verdict, FrameVerdict::accepted);
  EXPECT_EQ(agent.status().tick, 1003);
}

TEST(RetreatAgent, ChecksTheRobotIdBeforeAnythingElse) {
  RetreatAgent agent(2);
  Observation frame = frame_at(0, 0.03, 0, RobotPhase::inside, 3);
  frame.time = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(agent.on_frame(frame).verdict, FrameVerdict::wrong_robot);
  EXPECT_EQ(agent.frames()[FrameVerdict::wrong_robot], 1u);
  EXPECT_FALSE(agent.status().tick.has_value());
}

TEST(FrameVerdict, HasAReadableName) {
  EXPECT_EQ(to_string(FrameVerdict::accepted), "accepted");
  EXPECT_EQ(to_string(FrameVerdict::wrong_robot), "wrong_robot");
  EXPECT_EQ(to_string(FrameVerdict::stale_tick), "stale_tick");
  EXPECT_EQ(to_string(FrameVerdict::duplicate_tick), "duplicate_tick");
  EXPECT_EQ(to_string(FrameVerdict::bad_time), "bad_time");
}

}  // namespace
}  // namespace retreat::agent
