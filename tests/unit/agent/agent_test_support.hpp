#pragma once
/// @file
/// Frames and checks shared by the RetreatAgent tests.

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>

#include "retreat/agent/controller.hpp"
#include "retreat/agent/observation.hpp"
#include "retreat/agent/retreat_agent.hpp"

namespace retreat::agent::testing {

/// A frame of robot @p robot_id at @p tick, on a clock that reads tick·dt.
inline Observation frame_at(std::int64_t tick, double dt, std::uint32_t new_onsets = 0,
                            RobotPhase phase = RobotPhase::inside, std::uint32_t robot_id = 0) {
  Observation frame;
  frame.tick = tick;
  frame.time = static_cast<double>(tick) * dt;
  frame.phase = phase;
  frame.in_contact = new_onsets > 0;
  frame.new_onsets = new_onsets;
  frame.robot_id = robot_id;
  return frame;
}

/// A frame of robot 0 at @p tick, at @p clock's time for it.
inline Observation clock_frame(const FrameClock& clock, std::int64_t tick, std::uint32_t onsets,
                               RobotPhase phase = RobotPhase::inside) {
  Observation f;
  f.tick = tick;
  f.time = clock.time(tick);
  f.phase = phase;
  f.in_contact = onsets > 0;
  f.new_onsets = onsets;
  return f;
}

/// Short-window parameters for tests that need many decision steps: L = 3 s, dt = 0.03 s,
/// so decisions start at step 100.
inline AgentParams short_window_params(double gain = 0.2) {
  AgentParams params;
  params.L = 3.0;
  params.dt = 0.03;
  params.K_p = gain;
  return params;
}

/// A controller that always returns the same probability.
class FixedProbability final : public Controller {
 public:
  explicit FixedProbability(double p) : p_(p) {}
  double retreat_probability(const ControllerInput&) override { return p_; }
  std::string_view name() const override { return "fixed"; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<FixedProbability>(*this); }

 private:
  double p_;
};

/// A controller that always returns the same probability, from a chosen time inside on.
class FixedProbabilityFrom final : public Controller {
 public:
  FixedProbabilityFrom(double p, double first) : p_(p), first_(first) {}
  double retreat_probability(const ControllerInput&) override { return p_; }
  double first_decision_after(const AgentParams&) const override { return first_; }
  std::string_view name() const override { return "fixed-from"; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<FixedProbabilityFrom>(*this); }

 private:
  double p_;
  double first_;
};

/// Expects equal algorithm state (everything but the frame counters).
inline void expect_same_state(const AgentSnapshot& a, const AgentSnapshot& b) {
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.entry_time, b.entry_time);
  EXPECT_EQ(a.deciding, b.deciding);
  EXPECT_EQ(a.stopped, b.stopped);
  EXPECT_EQ(a.retreating, b.retreating);
  EXPECT_EQ(a.onsets_in_window, b.onsets_in_window);
  EXPECT_EQ(a.lambda_hat, b.lambda_hat);
  EXPECT_EQ(a.epsilon, b.epsilon);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.decision_steps, b.decision_steps);
  EXPECT_EQ(a.decision_time, b.decision_time);
}

}  // namespace retreat::agent::testing
