// The controllers' predictions (deploy/experiment/prediction.cpp): the exact population chain
// and the same chain run robot by robot, against the closed form they share.

#include "retreat/experiment/prediction.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <stdexcept>
#include <string>

#include "retreat/model/optimum.hpp"
#include "retreat/model/population.hpp"
#include "retreat/scenario/scenario.hpp"

namespace {

using retreat::experiment::predicted_population;
using retreat::experiment::robot_by_robot_chain;

const std::string scenarios = RETREAT_SCENARIOS;

// `influx-matching` with a negligible gain leaves at the constant rate μ = λ_in/λ* whatever it
// counts: with Poisson arrivals at λ_in|D| the robots inside are an M/M/∞ queue of mean
// λ_in|D|/μ = λ*|D| = N* (the initial robots' excess decays as e^(−μt), e^(−8) by t = 600 s).
retreat::scenario::Scenario steady_influx_matching() {
  auto s = retreat::scenario::load(scenarios + "/steady-influx.yaml",
                                   {"agent.controller=influx-matching"});
  s.agent.K_p = 1e-12;
  return s;
}

double last_half(const std::vector<double>& series, double dt, double duration) {
  return retreat::model::time_mean(series, dt, duration / 2.0, duration);
}

TEST(Prediction, BothChainsHoldAnEndlessQueueAtTheMOverMOverInfinityMean) {
  const auto s = steady_influx_matching();
  const double duration = 1200.0;
  const double area =
      3.14159265358979323846 * s.arena.semi_axis_x * s.arena.semi_axis_y;  // an ellipse
  const double optimum = retreat::model::lambda_star(s.model) * area;      // 4.55
  const auto exact = predicted_population(s, "influx-matching", duration);
  ASSERT_TRUE(exact.has_value());
  // The chain records N after the step's departures: a robot that arrived in the step may
  // already have left, N*·(1 − p) with p = μ·dt = 4·10⁻⁴.
  EXPECT_NEAR(last_half(*exact, s.agent.dt, duration), optimum, 0.01);
  // 200 runs: one run's time-mean over the 600 s has a standard deviation of about
  // √(2·N*/(μ·600 s)) = 1.07 robots (a Poisson(N*) count with correlation time 1/μ = 75 s), the
  // mean of 200 runs 0.076; 0.3 is four of those.
  const auto by_robot = robot_by_robot_chain(s, "influx-matching", duration, 200);
  EXPECT_NEAR(last_half(by_robot, s.agent.dt, duration), optimum, 0.3);
}

TEST(Prediction, TheRobotByRobotChainIsTheSameForTheSameScenario) {
  const auto s = retreat::scenario::load(scenarios + "/robotarium-2019.yaml", {});
  const auto a = robot_by_robot_chain(s, "adaptive-proportional", 300.0, 3);
  EXPECT_EQ(a, robot_by_robot_chain(s, "adaptive-proportional", 300.0, 3));
  ASSERT_EQ(a.size(), 10001U);
  EXPECT_EQ(a.front(), static_cast<double>(s.arena.robots_inside));
}

TEST(Prediction, TheRobotByRobotChainIsTheSameOnAnyNumberOfThreads) {
  // The runs shared among 1, 2, 3 and 7 threads (7 runs: one each), and more threads than runs.
  const auto s = retreat::scenario::load(scenarios + "/steady-influx.yaml", {});
  const auto one = robot_by_robot_chain(s, "paper", 600.0, 7, 1);
  for (const unsigned jobs : {2U, 3U, 7U, 16U}) {
    EXPECT_EQ(robot_by_robot_chain(s, "paper", 600.0, 7, jobs), one) << jobs << " threads";
  }
  // Not a constant: robots come and go in the endless queue.
  EXPECT_NE(*std::min_element(one.begin(), one.end()), *std::max_element(one.begin(), one.end()));
}

TEST(Prediction, OnlyCountOnlyRulesHaveAnExactChain) {
  const auto s = retreat::scenario::load(scenarios + "/robotarium-2019.yaml", {});
  for (const std::string rule :
       {"paper", "confident", "confident-proportional", "influx-matching"}) {
    EXPECT_TRUE(predicted_population(s, rule, 60.0).has_value()) << rule;
  }
  for (const std::string rule :
       {"influx-aware", "confident-influx-aware", "adaptive-proportional"}) {
    EXPECT_FALSE(predicted_population(s, rule, 60.0).has_value()) << rule;
  }
}

TEST(Prediction, TheRobotByRobotChainNeedsARun) {
  const auto s = retreat::scenario::load(scenarios + "/robotarium-2019.yaml", {});
  EXPECT_THROW(robot_by_robot_chain(s, "paper", 60.0, 0), std::invalid_argument);
}

}  // namespace
