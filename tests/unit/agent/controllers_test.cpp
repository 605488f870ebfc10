// The named controllers beside `paper` (agent/core; their designs and measured effects are in
// docs/experiments.md), and the one guarantee they all share: a controller sees only the
// robot's own data.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "retreat/agent/confident_controller.hpp"
#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/early_confident_controllers.hpp"
#include "retreat/agent/influx_aware_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

// --- Only the robot's own data, by construction ------------------------------------------
// ControllerInput is the whole of what a controller is given (Controller::retreat_probability
// takes nothing else, and agent_core is a PURE library that cannot link the transport, the
// scenario loader or the physics: deploy/cmake/RetreatHelpers.cmake refuses). The binding
// below compiles only while ControllerInput has exactly these ten members of these types; a
// field carrying ground truth or another robot's data cannot be added without editing it.
constexpr bool input_is_only_own_data() {
  using I = ControllerInput;
  static_assert(std::is_aggregate_v<I>);
  I* input = nullptr;
  if (input == nullptr) return true;  // never binds: only the declaration below matters
  auto& [time, time_inside, onsets, L, dt, lambda_hat, lambda_star, model, agent, window] = *input;
  static_assert(std::is_same_v<decltype(time), double>);
  static_assert(std::is_same_v<decltype(time_inside), double>);
  static_assert(std::is_same_v<decltype(onsets), std::uint64_t>);
  static_assert(std::is_same_v<decltype(L), double>);
  static_assert(std::is_same_v<decltype(dt), double>);
  static_assert(std::is_same_v<decltype(lambda_hat), double>);
  static_assert(std::is_same_v<decltype(lambda_star), double>);  // a function of `model` alone
  static_assert(std::is_same_v<decltype(model), const model::ModelParams&>);
  static_assert(std::is_same_v<decltype(agent), const AgentParams&>);
  static_assert(std::is_same_v<decltype(window), const OnsetWindow&>);
  return true;
}
static_assert(input_is_only_own_data());

// The robot's own window as the agent would hand it over: `onsets` onsets, at time t.
struct Step {
  model::ModelParams model;
  AgentParams agent;
  OnsetWindow window{90.0};

  ControllerInput at(double t, std::uint64_t onsets) const { return inside_for(t, t, onsets); }
  // The same at time t, `inside` seconds after the robot's entry.
  ControllerInput inside_for(double t, double inside, std::uint64_t onsets) const {
    return ControllerInput{t,     inside, onsets, agent.L, agent.dt, model::mle_density(onsets, model.delta, model.v, agent.L),
                           model::lambda_star(model), model, agent, window};
  }
  double lambda_star() const { return model::lambda_star(model); }
  // The window count whose MLE is closest to `lambda` [robots/m²].
  std::uint64_t onsets_for(double lambda) const {
    return static_cast<std::uint64_t>(std::lround(lambda * model::swept_rate(model) * agent.L));
  }
};

TEST(Controllers, AreAllRegisteredAfterThePaperController) {
  const auto names = controller_names();
  ASSERT_EQ(names.size(), 7U);
  EXPECT_EQ(names[0], "paper");
  EXPECT_EQ(names[1], "confident");
  EXPECT_EQ(names[2], "influx-aware");
  EXPECT_EQ(names[3], "confident-influx-aware");
  EXPECT_EQ(names[4], "confident-proportional");
  EXPECT_EQ(names[5], "influx-matching");
  EXPECT_EQ(names[6], "adaptive-proportional");
}

TEST(Controllers, ThoseBuiltOnThePapersLoopWaitOneWindowAndTheEarlyOnesDecideFromEntry) {
  const AgentParams agent;
  for (const auto& name : controller_names()) {
    const bool early =
        name == "confident-proportional" || name == "influx-matching" || name == "adaptive-proportional";
    EXPECT_EQ(make_controller(name)->first_decision_after(agent), early ? 0.0 : agent.L) << name;
  }
}

// --- confident ------------------------------------------------------------------------------

TEST(ConfidentController, WithZZeroTheLoweredEstimateIsTheMle) {
  const Step s;
  for (const std::uint64_t y : {0, 1, 7, 20, 1000}) {
    EXPECT_NEAR(lower_confidence_density(y, s.model, s.agent.L, 0.0),
                model::mle_density(y, s.model.delta, s.model.v, s.agent.L), 1e-12);
  }
}

TEST(ConfidentController, LowersTheCountByZPoissonStandardDeviations) {
  const Step s;
  const double c_L = model::swept_rate(s.model) * s.agent.L;  // onsets per unit density
  EXPECT_NEAR(lower_confidence_density(16, s.model, s.agent.L, 1.0), (16.0 - 4.0) / c_L, 1e-12);
  EXPECT_NEAR(lower_confidence_density(16, s.model, s.agent.L, 2.0), (16.0 - 8.0) / c_L, 1e-12);
  EXPECT_EQ(lower_confidence_density(1, s.model, s.agent.L, 2.0), 0.0);  // never negative
}

TEST(ConfidentController, StaysWhereThePaperWouldLeaveOnAnEstimateWithinOneSigmaOfTheOptimum) {
  const Step s;
  // λ* gives ≈ 6.9 onsets in L; 9 onsets put λ̂ above λ* but 9 − 3 below it.
  const std::uint64_t y = 9;
  const auto input = s.at(100.0, y);
  ASSERT_GT(input.lambda_hat, s.lambda_star());
  ASSERT_LT(lower_confidence_density(y, s.model, s.agent.L, 1.0), s.lambda_star());
  ConfidentController confident;
  EXPECT_EQ(confident.retreat_probability(input), 0.0);
  EXPECT_GT(make_controller("paper")->retreat_probability(input), 0.0);
}

TEST(ConfidentController, FarAboveTheOptimumLeavesAtThePaperRateOfTheLoweredEstimate) {
  const Step s;
  const std::uint64_t y = 40;
  const double low = lower_confidence_density(y, s.model, s.agent.L, 1.0);
  ASSERT_GT(low, s.lambda_star());
  ConfidentController confident;
  EXPECT_DOUBLE_EQ(confident.retreat_probability(s.at(100.0, y)),
                   model::epsilon(low, s.lambda_star(), s.agent.lambda_in, s.agent.K_p) * s.agent.dt);
}

TEST(ConfidentController, RejectsANegativeOrNonFiniteZ) {
  EXPECT_THROW(ConfidentController{-1.0}, std::invalid_argument);
  EXPECT_THROW(ConfidentController{NAN}, std::invalid_argument);
  EXPECT_THROW(InfluxAwareController{INFINITY}, std::invalid_argument);
}

// --- confident-proportional and influx-matching ---------------------------------------------

TEST(ConfidentPartialDensity, CountsOverTheTimeInsideUntilAWholeWindowThenOverL) {
  const Step s;
  const double c = model::swept_rate(s.model);
  // 30 s inside: 16 onsets are 16/(30c) robots/m², lowered by √16 = 4.
  EXPECT_EQ(counted_span(s.inside_for(130.0, 30.0, 16)), 30.0);
  EXPECT_NEAR(confident_partial_density(s.inside_for(130.0, 30.0, 16), 1.0), 12.0 / (c * 30.0), 1e-12);
  EXPECT_NEAR(confident_partial_density(s.inside_for(130.0, 30.0, 16), 0.0), 16.0 / (c * 30.0), 1e-12);
  // From L on it is lower_confidence_density over L.
  EXPECT_EQ(counted_span(s.inside_for(500.0, 400.0, 16)), s.agent.L);
  EXPECT_DOUBLE_EQ(confident_partial_density(s.inside_for(500.0, 400.0, 16), 1.0),
                   lower_confidence_density(16, s.model, s.agent.L, 1.0));
}

TEST(ConfidentPartialDensity, CorrectsForTheSensorsKnownMissedAndFalseOnsets) {
  // A sensor that keeps an onset with chance 1 − m and adds false ones at f reports a count of
  // mean ((1 − m)cλ + f)·w: the estimate subtracts f·w from the lowered count and divides by
  // (1 − m)c·w.
  Step s;
  s.agent.missed_onsets = 0.25;
  s.agent.false_onsets = 0.02;
  const double c = model::swept_rate(s.model);
  const auto input = s.inside_for(160.0, 60.0, 20);
  EXPECT_NEAR(confident_partial_density(input, 1.0), (20.0 - std::sqrt(20.0) - 0.02 * 60.0) / (0.75 * c * 60.0),
              1e-12);
  EXPECT_NEAR(confident_partial_density(input, 0.0), (20.0 - 0.02 * 60.0) / (0.75 * c * 60.0), 1e-12);
  // A count the false onsets alone explain is no density at all.
  EXPECT_EQ(confident_partial_density(s.inside_for(160.0, 60.0, 1), 0.0), 0.0);
  // The rules act on the corrected estimate: 7 onsets in 60 s stay below λ* as a perfect
  // sensor's count, and are above it once half of the onsets are known to be missed.
  Step perfect;
  Step half_missed;
  half_missed.agent.missed_onsets = 0.5;
  const auto seven = perfect.inside_for(160.0, 60.0, 7);
  ASSERT_LT(confident_partial_density(seven, 1.0), s.lambda_star());
  EXPECT_EQ(ConfidentProportionalController{}.retreat_probability(seven), 0.0);
  const auto seven_half = half_missed.inside_for(160.0, 60.0, 7);
  ASSERT_GT(confident_partial_density(seven_half, 1.0), s.lambda_star());
  EXPECT_GT(ConfidentProportionalController{}.retreat_probability(seven_half), 0.0);
}

TEST(ConfidentProportionalController, IsThePapersRateWithoutInfluxOnTheConfidentPartialEstimate) {
  Step s;
  ConfidentProportionalController rule;
  const double lambda_star = s.lambda_star();
  for (const double inside : {0.03, 10.0, 45.0, 90.0, 600.0}) {
    for (const std::uint64_t y : {0, 1, 5, 9, 16, 40, 200}) {
      const auto input = s.inside_for(1000.0, inside, y);
      const double low = confident_partial_density(input, 1.0);
      const double expected = low > lambda_star ? s.agent.K_p * (low - lambda_star) / low * s.agent.dt : 0.0;
      EXPECT_NEAR(rule.retreat_probability(input), expected, 1e-15) << inside << " s, y = " << y;
    }
  }
  // The configured influx plays no part.
  const double before = rule.retreat_probability(s.inside_for(100.0, 100.0, 40));
  ASSERT_GT(before, 0.0);
  s.agent.lambda_in = 0.5;
  EXPECT_EQ(rule.retreat_probability(s.inside_for(100.0, 100.0, 40)), before);
}

TEST(ConfidentProportionalController, AYoungRobotWithFewOnsetsStaysWhereTheMleWouldLeave) {
  const Step s;
  // 10 s inside, 2 onsets: the MLE over 10 s is 3.9 robots/m² (2.6 λ*), the lowered one
  // (2 − √2)/(10c) = 1.15 is below λ*.
  const auto input = s.inside_for(10.0, 10.0, 2);
  ASSERT_GT(confident_partial_density(input, 0.0), 2.0 * s.lambda_star());
  ASSERT_LT(confident_partial_density(input, 1.0), s.lambda_star());
  EXPECT_EQ(ConfidentProportionalController{}.retreat_probability(input), 0.0);
}

TEST(InfluxMatchingController, LeavesAtLambdaInOverLambdaStarBelowTheOptimum) {
  const Step s;
  InfluxMatchingController rule;
  const double matching = s.agent.lambda_in / s.lambda_star() * s.agent.dt;  // 0.02/1.5076 · 0.03
  for (const std::uint64_t y : {0, 3, 7, 9}) {
    EXPECT_DOUBLE_EQ(rule.retreat_probability(s.inside_for(200.0, 200.0, y)), matching) << y;
  }
  EXPECT_DOUBLE_EQ(rule.retreat_probability(s.inside_for(0.03, 0.03, 0)), matching);
}

TEST(InfluxMatchingController, AddsTheConfidentProportionalTermAboveTheOptimum) {
  Step s;
  InfluxMatchingController rule;
  ConfidentProportionalController proportional;
  const auto input = s.inside_for(300.0, 300.0, 40);
  ASSERT_GT(proportional.retreat_probability(input), 0.0);
  EXPECT_DOUBLE_EQ(rule.retreat_probability(input),
                   s.agent.lambda_in / s.lambda_star() * s.agent.dt + proportional.retreat_probability(input));
  // With no influx configured it is confident-proportional.
  s.agent.lambda_in = 0.0;
  for (const std::uint64_t y : {0, 9, 40}) {
    const auto in = s.inside_for(300.0, 300.0, y);
    EXPECT_EQ(rule.retreat_probability(in), proportional.retreat_probability(in)) << y;
  }
}

TEST(ConfidentProportionalController, RejectsANegativeOrNonFiniteZ) {
  EXPECT_THROW(ConfidentProportionalController{-0.5}, std::invalid_argument);
  EXPECT_THROW(InfluxMatchingController{NAN}, std::invalid_argument);
}

// --- influx-aware ---------------------------------------------------------------------------

// Runs the controller at every decision step from t0 to t1 with the onsets onsets(t) and
// returns the last step's probability.
template <typename Onsets>
double run_steps(Controller& controller, const Step& s, double t0, double t1, Onsets onsets) {
  double p = 0.0;
  for (std::int64_t k = 0;; ++k) {
    const double t = t0 + static_cast<double>(k) * s.agent.dt;
    if (t > t1) break;
    p = controller.retreat_probability(s.at(t, onsets(t)));
  }
  return p;
}

TEST(InfluxAwareController, CompensatesNoInfluxBeforeItHasTwoWindows) {
  const Step s;
  InfluxAwareController controller;
  const std::uint64_t y = s.onsets_for(3.0);  // well above λ*
  const double p = run_steps(controller, s, 90.0, 179.0, [&](double) { return y; });
  EXPECT_EQ(controller.last_influx_estimate(), 0.0);
  const double lambda_hat = s.at(0.0, y).lambda_hat;
  EXPECT_DOUBLE_EQ(p, model::epsilon(lambda_hat, s.lambda_star(), 0.0, s.agent.K_p) * s.agent.dt);
}

TEST(InfluxAwareController, ADensityHeldUpWhileTheRobotKeepsLeavingMeansAnInfluxOfLambdaIn) {
  // Above λ* the robot's own rate implies an outflow K_p (λ̂ − λ*) + λ̂_in > 0; a density that
  // nevertheless stays put over two windows can only be fed by arrivals: the estimate climbs
  // to the configured ceiling λ_in and the rule becomes the paper's.
  const Step s;
  InfluxAwareController controller;
  const std::uint64_t y = s.onsets_for(3.0);
  const double p = run_steps(controller, s, 90.0, 90.0 + 6 * s.agent.L, [&](double) { return y; });
  EXPECT_DOUBLE_EQ(controller.last_influx_estimate(), s.agent.lambda_in);
  EXPECT_DOUBLE_EQ(p, make_controller("paper")->retreat_probability(s.at(0.0, y)));
}

TEST(InfluxAwareController, BelowTheOptimumTheEstimateIsTheDensitysOwnRiseRate) {
  // Below λ* nobody leaves (ε = 0), so the influx is the measured rise: count y(t) = y0 + g·t
  // gives dλ̂/dt = g / (cL), under the ceiling λ_in.
  const Step s;
  const double c_L = model::swept_rate(s.model) * s.agent.L;
  const double g = 0.01;  // onsets per window per second: dλ̂/dt = 0.0022 robots/(m²·s)
  InfluxAwareController controller;
  // y must be whole: sample only where g·t is whole (every 100 s), hold it between.
  const auto onsets = [&](double t) { return static_cast<std::uint64_t>(std::floor(g * t)); };
  run_steps(controller, s, 90.0, 90.0 + 3 * s.agent.L, onsets);
  // Over the last L the count rose by g·L ± 1 (whole onsets): the estimate is within 1/(cL·L).
  EXPECT_NEAR(controller.last_influx_estimate(), g / c_L, 1.0 / (c_L * s.agent.L));
  EXPECT_GT(controller.last_influx_estimate(), 0.0);
  EXPECT_LT(controller.last_influx_estimate(), s.agent.lambda_in);
}

TEST(InfluxAwareController, AFallThatMatchesItsOwnOutflowMeansNoInflux) {
  // Density falling at exactly the rate the robot's own retreats imply: nothing came in.
  // Drive λ̂ down by dλ = −ε·λ·dt with the controller's own ε at every step (Euler).
  const Step s;
  const double c_L = model::swept_rate(s.model) * s.agent.L;
  InfluxAwareController controller;
  double lambda = 6.0;
  for (std::int64_t k = 0; static_cast<double>(k) * s.agent.dt <= 4 * s.agent.L; ++k) {
    const double t = 90.0 + static_cast<double>(k) * s.agent.dt;
    auto input = s.at(t, static_cast<std::uint64_t>(std::lround(lambda * c_L)));
    input.lambda_hat = lambda;  // the exact density, not a whole count
    const double p = controller.retreat_probability(input);
    lambda -= p / s.agent.dt * lambda * s.agent.dt;  // dλ = −ε·λ·dt
  }
  // (λ(t) − λ(t − L))/L of that Euler sequence is −(dt/L)·Σ ε·λ over the steps in the window,
  // and the estimate adds the mean of the same outflows: the two cancel up to one step's share
  // at the window's ends (1 in L/dt = 3,000), far below 1 % of λ_in.
  EXPECT_LT(controller.last_influx_estimate(), 0.01 * s.agent.lambda_in);
}

TEST(InfluxAwareController, TheConfidentVariantActsOnTheLoweredEstimate) {
  const Step s;
  const auto controller = make_controller("confident-influx-aware");
  EXPECT_EQ(controller->name(), "confident-influx-aware");
  const std::uint64_t y = 9;  // λ̂ above λ*, one σ below it not
  EXPECT_EQ(controller->retreat_probability(s.at(100.0, y)), 0.0);
  const std::uint64_t high = 40;
  const double low = lower_confidence_density(high, s.model, s.agent.L, 1.0);
  EXPECT_DOUBLE_EQ(controller->retreat_probability(s.at(100.03, high)),
                   model::epsilon(low, s.lambda_star(), 0.0, s.agent.K_p) * s.agent.dt);
}

// --- What a rule says of itself (Controller::count_only, corrects_sensor) --------------------
// The experiments trust these: the exact chain predicts only count-only rules, the noise
// experiment tells only correcting rules the sensor's rates. Each claim is checked on the rule.

// n onsets at the middles of n equal parts of (from, to): none on a step's time.
std::vector<double> spread(int n, double from, double to) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(from + (i + 0.5) * (to - from) / n);
  return t;
}

// A robot inside D from t = 0 with the sorted `onsets`, each added to its own window as the
// agent adds them, stepped every dt up to `seconds` by a new rule `name`: the chance at each
// step the rule decides.
std::vector<double> chances(const std::string& name, const AgentParams& agent, const std::vector<double>& onsets,
                            double seconds) {
  const model::ModelParams model;
  OnsetWindow window(agent.L);
  const auto rule = make_controller(name);
  std::vector<double> out;
  std::size_t added = 0;
  for (std::int64_t k = 1; static_cast<double>(k) * agent.dt <= seconds + 1e-9; ++k) {
    const double t = static_cast<double>(k) * agent.dt;
    while (added < onsets.size() && onsets[added] <= t) window.add(onsets[added++]);
    if (t < rule->first_decision_after(agent)) continue;
    const std::uint64_t y = window.count_at(t);
    out.push_back(rule->retreat_probability(
        {t, t, y, agent.L, agent.dt, model::mle_density(y, model.delta, model.v, agent.L), model::lambda_star(model),
         model, agent, window}));
  }
  return out;
}

TEST(Controllers, ThoseThatSayTheyAreCountOnlyGiveTheSameChanceForTheSameCountWhateverCameBefore) {
  const AgentParams agent;
  const double end = 400.0, from = end - agent.L;  // the last step's window: (from, end]
  int count_only = 0;
  for (const auto& name : controller_names()) {
    if (!make_controller(name)->count_only()) continue;
    ++count_only;
    for (const int y : {0, 4, 8, 16, 32}) {
      // Crowded before the window and y onsets spread over it; calm before and y onsets at its end.
      auto crowded = spread(120, 0.0, from), calm = spread(5, 0.0, from);
      for (const double t : spread(y, from, end)) crowded.push_back(t);
      for (const double t : spread(y, end - 10.0, end)) calm.push_back(t);
      EXPECT_EQ(chances(name, agent, crowded, end).back(), chances(name, agent, calm, end).back())
          << name << ", " << y << " onsets in the window";
    }
  }
  EXPECT_EQ(count_only, 4);  // paper, confident, confident-proportional, influx-matching
}

TEST(Controllers, ThoseThatSayTheyCorrectForTheSensorReadItsRatesAndNoOtherDoes) {
  AgentParams plain, told;
  told.missed_onsets = 0.3;
  told.false_onsets = 0.05;
  for (const auto& name : controller_names()) {
    bool differs = false;
    for (const double rate : {0.05, 0.1, 0.2, 0.4, 0.8}) {  // onsets per second, calm to crowded
      const auto onsets = spread(static_cast<int>(rate * 300.0), 0.0, 300.0);
      differs = differs || chances(name, plain, onsets, 300.0) != chances(name, told, onsets, 300.0);
    }
    EXPECT_EQ(differs, make_controller(name)->corrects_sensor()) << name;
  }
}

}  // namespace
}  // namespace retreat::agent
