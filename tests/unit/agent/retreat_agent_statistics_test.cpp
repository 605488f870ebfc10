#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>

#include "agent_test_support.hpp"
#include "retreat/agent/early_confident_controllers.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

using testing::frame_at;
using testing::short_window_params;

TEST(RetreatAgent, RetreatsAtEachStepWithProbabilityEpsilonTimesDt) {
  // L = 10 s, dt = 1 s, K_p = 0.5 /s; 5 onsets at t = 1 s, none after. Steps 10 and 11 both
  // see exactly those 5 onsets ([0, 10] and [1, 11], the window being closed), so
  // λ̂ = 5/(cL) = 9.82 and p = ε(λ̂)·dt = 0.4253 at both; step 12 sees none.
  // Over n = 20000 robots (independent seeds) the retreats at step 10 are Binomial(n, p), and
  // the retreats at step 11 among the m robots still deciding are Binomial(m, p) (each coin is
  // independent of the previous ones). With n·p, n·(1 − p) > 8000 the normal approximation is
  // excellent: a tolerance of 5 standard deviations sqrt(p(1 − p)/n) per check fails a correct
  // agent with probability 5.7e-7 each, 1.1e-6 for both.
  const model::ModelParams model;
  AgentParams params;
  params.L = 10.0;
  params.dt = 1.0;
  params.K_p = 0.5;
  const double lambda_hat = model::mle_density(5, model.delta, model.v, params.L);
  const double p =
      model::epsilon(lambda_hat, model::lambda_star(model), params.lambda_in, params.K_p) *
      params.dt;
  ASSERT_GT(p, 0.3);
  ASSERT_LT(p, 0.6);

  const int robots = 20000;
  int retreated_at_10 = 0;
  int deciding_at_11 = 0;
  int retreated_at_11 = 0;
  for (int id = 0; id < robots; ++id) {
    const auto robot_id = static_cast<std::uint32_t>(id);
    RetreatAgent agent(robot_id, model, params, nullptr,
                       seed_for(2019, robot_id, Stream::agent_decision));
    for (std::int64_t tick = 0; tick <= 9; ++tick) {
      agent.on_frame(frame_at(tick, params.dt, tick == 1 ? 5 : 0, RobotPhase::inside, robot_id));
    }
    if (agent.on_frame(frame_at(10, params.dt, 0, RobotPhase::inside, robot_id)).retreat_now) {
      ++retreated_at_10;
      continue;
    }
    ++deciding_at_11;
    if (agent.on_frame(frame_at(11, params.dt, 0, RobotPhase::inside, robot_id)).retreat_now) {
      ++retreated_at_11;
    }
    ASSERT_EQ(agent.status().lambda_hat, lambda_hat);
    ASSERT_NEAR(agent.status().epsilon * params.dt, p, 1e-15);
  }
  const double sigma_10 = std::sqrt(p * (1.0 - p) / robots);
  EXPECT_NEAR(static_cast<double>(retreated_at_10) / robots, p, 5.0 * sigma_10);
  const double sigma_11 = std::sqrt(p * (1.0 - p) / deciding_at_11);
  EXPECT_NEAR(static_cast<double>(retreated_at_11) / deciding_at_11, p, 5.0 * sigma_11);
}

TEST(RetreatAgent, UnderInfluxMatchingARobotWithoutEncountersStaysLambdaStarOverLambdaInOnAverage) {
  // influx-matching leaves at ε = λ_in/λ* (= 0.0133 /s, experiment parameters) at every step from
  // entry while the confident estimate is not above λ* (no onsets at all here): each step's coin
  // retreats with p = ε·dt = 3.98e-4, so the step of the retreat is geometric and the time inside
  // k·dt has mean dt/p = λ*/λ_in = 75.4 s, the mean stay that makes the M/G/∞ mean population
  // λ_in|D| · λ*/λ_in = λ*|D|. Over n = 4000 robots (independent seeds) the sample mean has a
  // standard error of sqrt(1 − p)/p·dt/sqrt(n) = 1.19 s; 5 standard errors (6.0 s) fail a correct
  // agent with probability 5.7e-7. The decision rule is also checked exactly: every retreat is
  // at a step time, none before the first step.
  const model::ModelParams model;
  const AgentParams params;
  const double p = params.lambda_in / model::lambda_star(model) * params.dt;
  const double mean_stay = params.dt / p;
  const int robots = 4000;
  double sum = 0.0;
  for (int id = 0; id < robots; ++id) {
    const auto robot_id = static_cast<std::uint32_t>(id);
    RetreatAgent agent(robot_id, model, params, std::make_unique<InfluxMatchingController>(),
                       seed_for(2026, robot_id, Stream::agent_decision));
    std::int64_t tick = 0;
    while (!agent.on_frame(frame_at(tick, params.dt, 0, RobotPhase::inside, robot_id)).retreat_now) {
      ++tick;
      ASSERT_LT(tick, 2'000'000) << "robot " << id << " never left";
    }
    ASSERT_GE(tick, 1);  // entry at tick 0, first step k = 1
    sum += static_cast<double>(tick) * params.dt;
  }
  const double standard_error = std::sqrt(1.0 - p) / p * params.dt / std::sqrt(robots);
  EXPECT_NEAR(sum / robots, mean_stay, 5.0 * standard_error);
  EXPECT_NEAR(mean_stay, model::lambda_star(model) / params.lambda_in, 1e-9);
}

/// Runs one robot for up to 20000 lockstep frames with a steady onset stream (λ̂ ≈ 140,
/// p ≈ 0.015 per step) and returns the step time of its retreat decision, if any.
std::optional<double> decision_time(std::uint64_t seed) {
  const AgentParams params = short_window_params(0.5);
  RetreatAgent agent(0, {}, params, nullptr, seed);
  for (std::int64_t tick = 0; tick < 20000 && !agent.retreating(); ++tick) {
    agent.on_frame(frame_at(tick, params.dt, tick % 10 == 0 ? 2 : 0));
  }
  return agent.status().decision_time;
}

TEST(RetreatAgent, MakesTheSameDecisionsWithTheSameSeed) {
  for (std::uint64_t robot = 0; robot < 10; ++robot) {
    const std::uint64_t seed =
        seed_for(5, static_cast<std::int64_t>(robot), Stream::agent_decision);
    const std::optional<double> first = decision_time(seed);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(decision_time(seed), first);
  }
}

TEST(RetreatAgent, MakesDifferentDecisionsWithDifferentSeeds) {
  // The decision step is geometric with p ≈ 0.015 (after the first L), so two independent
  // seeds decide at the same step with probability p/(2 − p) ≈ 0.0075. Over 10 consecutive
  // seed pairs, 3 or more coincidences happen with probability C(10,3)·0.0075³ ≈ 5e-5.
  int coincidences = 0;
  for (std::int64_t robot = 0; robot < 10; ++robot) {
    const auto a = decision_time(seed_for(5, robot, Stream::agent_decision));
    const auto b = decision_time(seed_for(5, robot + 1, Stream::agent_decision));
    ASSERT_TRUE(a.has_value() && b.has_value());
    coincidences += *a == *b ? 1 : 0;
  }
  EXPECT_LE(coincidences, 2);
}

}  // namespace
}  // namespace retreat::agent
