// `adaptive-proportional` (agent/core/src/adaptive_proportional_controller.cpp): the span it
// counts over (AdaptiveSpan) and its rate, against closed forms, driven through a real
// OnsetWindow as the agent drives it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "retreat/agent/adaptive_proportional_controller.hpp"
#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/early_confident_controllers.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

// One robot, inside D from t = 0, its onsets at `onsets` (sorted). step(t) adds the onsets up
// to t to the robot's window, as the agent does with each frame, and hands the step to the
// controller.
struct Robot {
  model::ModelParams model;
  AgentParams agent;
  OnsetWindow window{agent.L};
  std::vector<double> onsets;
  std::size_t added = 0;
  double last_step = 0.0;  ///< time of the last step run()

  ControllerInput input(double t) {
    while (added < onsets.size() && onsets[added] <= t) window.add(onsets[added++]);
    const std::uint64_t y = window.count_at(t);
    return ControllerInput{t,       t,        y,
                           agent.L, agent.dt, model::mle_density(y, model.delta, model.v, agent.L),
                           model::lambda_star(model), model, agent, window};
  }
  // Every step k·dt in (0, t1]; the last step's probability.
  double run(Controller& controller, double t1) {
    double p = 0.0;
    for (std::int64_t k = 1; static_cast<double>(k) * agent.dt <= t1 + 1e-9; ++k) {
      last_step = static_cast<double>(k) * agent.dt;
      p = controller.retreat_probability(input(last_step));
    }
    return p;
  }
  double lambda_star() const { return model::lambda_star(model); }
  double c() const { return model::swept_rate(model); }
};

// n onsets spread evenly over (from, to), at the middles of n equal parts (so that none falls
// on a step's time or a half's boundary).
std::vector<double> spread(int n, double from, double to) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(from + (i + 0.5) * (to - from) / n);
  return t;
}

std::vector<double> joined(std::vector<double> a, const std::vector<double>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

double proportional_rate(const Robot& r, double lambda_low) {
  return model::epsilon(lambda_low, r.lambda_star(), 0.0, r.agent.K_p) * r.agent.dt;
}

TEST(AdaptiveProportional, IsRegisteredAndDecidesFromEntry) {
  ASSERT_TRUE(is_controller_name("adaptive-proportional"));
  const auto rule = make_controller("adaptive-proportional");
  EXPECT_EQ(rule->name(), "adaptive-proportional");
  EXPECT_EQ(rule->first_decision_after(AgentParams{}), 0.0);
}

TEST(AdaptiveProportional, AtASteadyDensityTheSpanIsTheTimeInsideAndOutgrowsTheWindow) {
  // One onset every 4 s for 600 s: the halves are equal, nothing is forgotten, and the count
  // covers all 600 s although the paper's window holds only the last L = 90 s.
  Robot r;
  r.onsets = spread(150, 0.0, 600.0);
  AdaptiveProportionalController rule;
  const double p = r.run(rule, 600.0);
  EXPECT_EQ(rule.span().halvings(), 0);
  EXPECT_EQ(rule.span().start(), 0.0);
  EXPECT_EQ(rule.span().onsets(), 150U);
  EXPECT_LT(r.window.held(), 25U);
  // 150 onsets in 600 s: λ_low = (150 − √150)/(600c) = 3.0 λ*: the paper's proportional rate.
  const double lambda_low = (150.0 - std::sqrt(150.0)) / (r.last_step * r.c());
  ASSERT_GT(lambda_low, r.lambda_star());
  EXPECT_NEAR(p, proportional_rate(r, lambda_low), 1e-15);
}

TEST(AdaptiveProportional, AClearFallForgetsTheEarlierHalf) {
  // 60 onsets in the first 100 s, then 2 in the next 100 s. Once the quiet part is as long as
  // the crowded one, the later half holds clearly fewer (60 − 2 > √62 at t = 200; earlier, as
  // soon as the fall shows): the crowded part is forgotten but for its last onset or so, and the
  // estimate is the later count's, far below λ*: no exit.
  Robot r;
  r.onsets = joined(spread(60, 0.0, 100.0), {140.0, 180.0});
  AdaptiveProportionalController rule;
  const double p = r.run(rule, 200.0);
  EXPECT_GE(rule.span().halvings(), 1);
  EXPECT_GE(rule.span().start(), 90.0);
  EXPECT_LE(rule.span().onsets(), 3U);
  EXPECT_EQ(p, 0.0);
  // confident-proportional still counts the crowded past at t = 150: 30 of its 90 s are in it.
  Robot same;
  same.onsets = r.onsets;
  ConfidentProportionalController window_rule;
  EXPECT_GT(same.run(window_rule, 150.0), 0.0);
}

TEST(AdaptiveProportional, HalvesOnlyOnAFallOfMoreThanOneStandardDeviation) {
  // 30 onsets per 100 s, then 24: a fall of 6 < √54 = 7.3 is noise, and the span is kept.
  Robot r;
  r.onsets = joined(spread(30, 0.0, 100.0), spread(24, 100.0, 200.0));
  AdaptiveProportionalController rule;
  r.run(rule, 200.0);
  EXPECT_EQ(rule.span().halvings(), 0);
  EXPECT_EQ(rule.span().onsets(), 54U);
}

TEST(AdaptiveProportional, ARiseKeepsTheSpan) {
  // 5 onsets in the first 100 s, then 60: the later half is crowded, the span stays [0, 200]
  // and the estimate stays the lower, whole count's.
  Robot r;
  r.onsets = joined(spread(5, 0.0, 100.0), spread(60, 100.0, 200.0));
  AdaptiveProportionalController rule;
  const double p = r.run(rule, 200.0);
  EXPECT_EQ(rule.span().halvings(), 0);
  EXPECT_EQ(rule.span().onsets(), 65U);
  const double lambda_low = (65.0 - std::sqrt(65.0)) / (r.last_step * r.c());
  EXPECT_NEAR(p, proportional_rate(r, lambda_low), 1e-15);
}

TEST(AdaptiveProportional, OnsetsAddedAtAnInstantAlreadySteppedAreCountedOnce) {
  // A frame's onsets can reach the window after a step at the same time (OnsetWindow merges
  // them into that instant's entry): each is counted once, at the next step.
  Robot r;
  AdaptiveProportionalController rule;
  r.window.add(0.03, 2);
  rule.retreat_probability(r.input(0.03));
  EXPECT_EQ(rule.span().onsets(), 2U);
  r.window.add(0.03, 3);
  rule.retreat_probability(r.input(0.06));
  EXPECT_EQ(rule.span().onsets(), 5U);
  EXPECT_EQ(rule.span().halvings(), 0);
}

TEST(AdaptiveProportional, OnsetsAddedLaterAtAnInstantAlreadyForgottenStayForgotten) {
  // Two onsets at 0.03 s, then none: by 1 s the later half of the span is clearly emptier and
  // the instant 0.03 s is forgotten. Onsets the window adds to that instant afterwards belong to
  // the forgotten part too.
  Robot r;
  AdaptiveProportionalController rule;
  r.window.add(0.03, 2);
  r.run(rule, 1.0);
  ASSERT_GE(rule.span().halvings(), 1);
  ASSERT_EQ(rule.span().onsets(), 0U);
  r.window.add(0.03, 3);
  rule.retreat_probability(r.input(r.last_step + r.agent.dt));
  EXPECT_EQ(rule.span().onsets(), 0U);
}

TEST(AdaptiveProportional, IgnoresOnsetsLaterThanTheStep) {
  Robot r;
  AdaptiveProportionalController rule;
  r.window.add(0.09, 4);  // held, but after the step at 0.03
  rule.retreat_probability(r.input(0.03));
  EXPECT_EQ(rule.span().onsets(), 0U);
  rule.retreat_probability(r.input(0.09));
  EXPECT_EQ(rule.span().onsets(), 4U);
}

TEST(AdaptiveProportional, ACloneLooksAheadWithoutChangingTheOriginal) {
  Robot r;
  r.onsets = spread(200, 0.0, 400.0);
  AdaptiveProportionalController rule;
  r.run(rule, 100.0);
  const auto onsets = rule.span().onsets();
  auto copy = rule.clone();
  Robot ahead = r;  // the same window, stepped further by the copy only
  for (std::int64_t k = 1; k <= 3000; ++k) {
    copy->retreat_probability(ahead.input(100.0 + static_cast<double>(k) * r.agent.dt));
  }
  EXPECT_GT(static_cast<const AdaptiveProportionalController&>(*copy).span().onsets(), onsets);
  EXPECT_EQ(rule.span().onsets(), onsets);
}

TEST(AdaptiveProportional, CorrectsForTheSensorsKnownRatesLikeConfidentProportional) {
  Robot r;
  r.agent.missed_onsets = 0.25;
  r.agent.false_onsets = 0.02;
  r.onsets = spread(100, 0.0, 300.0);  // 100 onsets in 300 s, no fall
  AdaptiveProportionalController rule;
  const double p = r.run(rule, 300.0);
  ASSERT_EQ(rule.span().halvings(), 0);
  const double w = r.last_step;
  const double lambda_low = (100.0 - 10.0 - 0.02 * w) / (0.75 * r.c() * w);
  ASSERT_GT(lambda_low, r.lambda_star());
  EXPECT_NEAR(p, proportional_rate(r, lambda_low), 1e-15);
}

TEST(AdaptiveProportional, RejectsANegativeOrNonFiniteZ) {
  EXPECT_THROW(AdaptiveProportionalController{-1.0}, std::invalid_argument);
  EXPECT_THROW(AdaptiveProportionalController{NAN}, std::invalid_argument);
  EXPECT_THROW(AdaptiveSpan{INFINITY}, std::invalid_argument);
}

}  // namespace
}  // namespace retreat::agent
