// RetreatAgent::take_quiet_frames: the frames a plan covers, taken in one go where frame by frame
// they would decide nothing. It must leave the agent exactly as on_frame does, frame by frame,
// and stop exactly at the frame before the first that takes a decision step: one frame later and
// a decision (a possible retreat) would be skipped.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>

#include "agent_test_support.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/seed.hpp"

namespace retreat::agent {
namespace {

using testing::clock_frame;
using testing::expect_same_state;
using testing::short_window_params;


void expect_same(const RetreatAgent& a, const RetreatAgent& b) {
  expect_same_state(a.status(), b.status());
  EXPECT_EQ(a.frames(), b.frames());
}

/// Frame clocks against the agents' dt = 0.03 s: one step per frame (kinetic), the physical
/// world's three 0.01 s physics steps per frame, a step every third frame, and several steps per
/// frame (1/0.03 and 0.07 are not multiples of each other: step and frame times never coincide
/// exactly, so the 1e-9·dt tolerance of take_due_steps decides).
constexpr FrameClock clocks[] = {{1, 0.03}, {3, 0.01}, {1, 0.01}, {1, 0.07}};

/// An agent whose first decision step comes at @p first inside: the paper's L = 3 s (`paper`),
/// or earlier, as controllers with Controller::first_decision_after < L have it.
RetreatAgent agent_deciding_from(double first) {
  return RetreatAgent(0, {}, short_window_params(), std::make_unique<testing::FixedProbabilityFrom>(0.0, first),
                      seed_for(7, 0, Stream::agent_decision));
}

TEST(RetreatAgentQuietFrames, StopBeforeTheFirstDecisionStepAndLeaveTheFrameByFrameState) {
  int stretches = 0;
  int stopped_early = 0;
  for (const FrameClock& clock : clocks) {
    for (const double first : {3.0, 0.3, 0.0, 0.031}) {
      for (std::int64_t entry = 0; entry < 3; ++entry) {
        RetreatAgent base = agent_deciding_from(first);
        for (std::int64_t t = 0; t < entry; ++t) base.on_frame(clock_frame(clock, t, 0, RobotPhase::waiting));
        // From every frame before and just after the first decision step, a quiet stretch of
        // up to 150 frames.
        const auto frames_past_first = static_cast<std::int64_t>(3.2 / clock.time(1)) + 10;
        for (std::int64_t last = entry; last < entry + frames_past_first; ++last) {
          base.on_frame(clock_frame(clock, last, last % 7 == 0 ? 1 : 0));
          for (const std::int64_t through : {last + 1, last + 2, last + 45, last + 150}) {
            // Frame by frame: the last frame before the first that takes a decision step.
            RetreatAgent by_frame(base);
            std::int64_t expected = last;
            std::optional<RetreatAgent> at_expected(by_frame);
            for (std::int64_t t = last + 1; t <= through; ++t) {
              const auto decided_before = by_frame.status().decision_steps;
              by_frame.on_frame(clock_frame(clock, t, 0));
              if (by_frame.status().decision_steps != decided_before) break;
              expected = t;
              at_expected.emplace(by_frame);
            }
            RetreatAgent at_once(base);
            EXPECT_EQ(base.quiet_through(clock, RobotPhase::inside, through), expected);
            const std::int64_t taken = at_once.take_quiet_frames(clock, RobotPhase::inside, through);
            ASSERT_EQ(taken, expected) << "clock " << clock.multiplier << " x " << clock.period << ", first "
                                       << first << ", entry " << entry << ", last " << last << ", through "
                                       << through;
            expect_same(at_once, *at_expected);
            // And the frames after them are taken as if they had come one by one.
            RetreatAgent after(*at_expected);
            for (std::int64_t t = taken + 1; t <= taken + 5; ++t) {
              const auto a = at_once.on_frame(clock_frame(clock, t, 0));
              const auto b = after.on_frame(clock_frame(clock, t, 0));
              EXPECT_EQ(a.retreat_now, b.retreat_now);
            }
            expect_same(at_once, after);
            if (HasFailure()) return;
            ++stretches;
            if (taken < through) ++stopped_early;
          }
        }
      }
    }
  }
  // Both kinds happened: stretches taken whole, and stretches that stop at a decision step.
  EXPECT_GT(stretches, 1000);
  EXPECT_GT(stopped_early, 100);
  EXPECT_GT(stretches - stopped_early, 100);
}

TEST(RetreatAgentQuietFrames, AWaitingStoppedOrDepartingRobotsFramesAreAllQuiet) {
  const FrameClock clock{1, 0.03};
  // Waiting (not inside yet): every frame is only counted.
  RetreatAgent waiting = agent_deciding_from(0.0);
  waiting.on_frame(clock_frame(clock, 0, 0, RobotPhase::waiting));
  RetreatAgent waiting_by_frame(waiting);
  EXPECT_EQ(waiting.take_quiet_frames(clock, RobotPhase::waiting, 400), 400);
  for (std::int64_t t = 1; t <= 400; ++t) waiting_by_frame.on_frame(clock_frame(clock, t, 0, RobotPhase::waiting));
  expect_same(waiting, waiting_by_frame);
  EXPECT_EQ(waiting.frames().accepted(), 401u);

  // The first `inside` frame is the robot's entry: it is left to on_frame.
  EXPECT_EQ(waiting.take_quiet_frames(clock, RobotPhase::inside, 500), 400);

  // Departing (a `retreating` phase stops the agent) and departed: only counted.
  RetreatAgent inside = agent_deciding_from(0.0);
  inside.on_frame(clock_frame(clock, 0, 0));
  RetreatAgent inside_by_frame(inside);
  EXPECT_EQ(inside.take_quiet_frames(clock, RobotPhase::retreating, 90), 90);
  for (std::int64_t t = 1; t <= 90; ++t) inside_by_frame.on_frame(clock_frame(clock, t, 0, RobotPhase::retreating));
  expect_same(inside, inside_by_frame);
  EXPECT_TRUE(inside.stopped());
  EXPECT_EQ(inside.take_quiet_frames(clock, RobotPhase::inside, 200), 200) << "a stopped agent takes no step";
}

TEST(RetreatAgentQuietFrames, FramesOnAClockThatGoesBackAreLeftToOnFrameToRefuse) {
  RetreatAgent agent = agent_deciding_from(3.0);
  agent.on_frame(clock_frame({1, 0.03}, 100, 0));  // t = 3 s
  EXPECT_EQ(agent.take_quiet_frames({1, 0.001}, RobotPhase::inside, 150), 100);  // tick 101 at 0.101 s
  EXPECT_EQ(agent.frames().accepted(), 1u);
  EXPECT_EQ(agent.take_quiet_frames({1, 0.03}, RobotPhase::inside, 100), 100) << "no frame after the last";
  EXPECT_THROW(agent.take_quiet_frames({0, 0.03}, RobotPhase::inside, 150), std::invalid_argument);
  RetreatAgent fresh = agent_deciding_from(3.0);
  EXPECT_THROW(fresh.take_quiet_frames({1, 0.03}, RobotPhase::inside, 10), std::logic_error);
}

}  // namespace
}  // namespace retreat::agent
