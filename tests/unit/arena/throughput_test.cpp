// Swarm output T(λ)λ of the physical world against the CTMC (MODEL.md §3, §6).

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "paper_setups.hpp"
#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

constexpr std::uint32_t robots = 200;
constexpr double warm_up = 250.0;    // s: two delivery cycles (1/Ω_p + 1/Ω_d ≈ 124 s)
constexpr double duration = 2500.0;  // s
constexpr double lambda_fit = 0.99;  // where ρ is fitted, as in the paper
constexpr double lambda_beyond = 4.0;  // past the CTMC's range of validity (below)

struct Point {
  double output = 0.0;  // deliveries per second per m² (T(λ)·λ measured)
  double deliveries = 0.0;
  double rho_robot = 0.0;  // 1 / mean robot-level contact duration
  double rho_pair = 0.0;
  double free_fraction = 0.0;  // the share of robot-time with no robot within 2δ
  double contact_load = 0.0;   // x = Ω_c/ρ_pair: pair contacts open per robot, on average
};

/// One run per density, cached within the process. v = 0.1 exactly as in the paper; the world is
/// encounter_validation() with time stretched by 10, so ρ fitted here is the v = 0.1 value.
const Point& simulate(double lambda) {
  static std::map<double, Point> cache;
  const auto found = cache.find(lambda);
  if (found != cache.end()) {
    return found->second;
  }
  WorldParams p = testing::throughput_curve(robots, lambda);
  p.record_encounters = lambda == lambda_fit || lambda == lambda_beyond;  // bookkeeping only
  auto world = make_world(p);
  for (long k = 0; k < std::lround(warm_up / p.tick_dt); ++k) {
    world->step_tick();
  }
  world->take_contact_records();
  const std::uint64_t before = world->telemetry().deliveries;
  double pair_sum = 0.0;
  double pair_n = 0.0;
  double robot_sum = 0.0;
  double robot_n = 0.0;
  for (long k = 0; k < std::lround(duration / p.tick_dt); ++k) {
    world->step_tick();
    for (const ContactRecord& c : world->take_contact_records()) {
      if (c.other == no_robot) {
        robot_sum += c.end - c.start;
        robot_n += 1.0;
      } else {
        pair_sum += c.end - c.start;
        pair_n += 1.0;
      }
    }
  }
  Point point;
  point.deliveries = static_cast<double>(world->telemetry().deliveries - before);
  point.output = point.deliveries / (duration * p.width * p.height);
  point.rho_robot = robot_n / robot_sum;
  point.rho_pair = pair_n / pair_sum;
  const double robot_time = robots * duration;
  point.free_fraction = 1.0 - robot_sum / robot_time;
  point.contact_load = 2.0 * pair_sum / robot_time;  // each pair contact holds two robots
  return cache[lambda] = point;
}

/// T(λ)λ = 2δv·(λ_pλ_d/(λ_p+λ_d))/(1 + cλ/ρ)·λ [deliveries/(s·m²)].
double ctmc_output(const WorldParams& p, double lambda, double rho) {
  const double harmonic = p.lambda_p * p.lambda_d / (p.lambda_p + p.lambda_d);
  const double c = testing::swept_area_rate(p);
  return 2.0 * p.delta * p.v * harmonic / (1.0 + c * lambda / rho) * lambda;
}

class PhysicsThroughput : public ::testing::TestWithParam<double> {};

// Tolerance: 20 % (the task's specification). Statistical noise is far smaller: ≥ 1500
// deliveries per point, delivery counts of 200 independent-ish robots with a per-robot
// coefficient of variation near 1 → relative sd ≤ 3 %, so a 20 % miss is a model or physics
// discrepancy, not chance (P(|Z| > 6.7) < 1e-10). ρ is the robot-level fit at λ = 0.99
// (the CTMC's fc/lc sojourn); the pair-level fit is recorded beside it.
TEST_P(PhysicsThroughput, SimulatedOutputIsWithinTwentyPercentOfTheCtmcCurve) {
  const double lambda = GetParam();
  const WorldParams p = testing::throughput_curve(robots, lambda);
  const Point& fit = simulate(lambda_fit);
  const Point& point = simulate(lambda);
  const double predicted = ctmc_output(p, lambda, fit.rho_robot);
  const double ratio = point.output / predicted;
  RecordProperty("lambda", std::to_string(lambda));
  RecordProperty("simulated_output", std::to_string(point.output));
  RecordProperty("ctmc_output", std::to_string(predicted));
  RecordProperty("ratio", std::to_string(ratio));
  RecordProperty("ctmc_output_with_pair_rho", std::to_string(ctmc_output(p, lambda, fit.rho_pair)));
  RecordProperty("rho_robot_fit", std::to_string(fit.rho_robot));
  RecordProperty("rho_pair_fit", std::to_string(fit.rho_pair));
  RecordProperty("deliveries", std::to_string(point.deliveries));
  ASSERT_GT(point.deliveries, 1500.0);
  EXPECT_NEAR(ratio, 1.0, 0.20) << "λ = " << lambda << ": simulated " << point.output << ", CTMC "
                                << predicted << " (ρ = " << fit.rho_robot << ")";
}

INSTANTIATE_TEST_SUITE_P(PaperDensities, PhysicsThroughput,
                         ::testing::Values(0.25, 0.5, 0.99, 2.0));

// λ = 4 is past the CTMC's range of validity, and this test holds the known disagreement and its
// cause, so that a change in either shows. At λ = 4 the 2δ-discs cover 15 % of D and a robot's
// pair contacts overlap: they behave as independent intervals (M/G/∞), so a robot is free a
// fraction e^(−x) of the time (x = Ω_c/ρ_pair, the pair contacts open per robot on average),
// while the CTMC, which admits one encounter at a time, gives 1/(1 + x). Equivalently the
// robot-level ρ falls with λ (2.6 at λ = 0.99, 1.8 at λ = 4, v = 1), which a constant-ρ CTMC
// cannot follow, and the simulated output falls short of the CTMC's (measured ratio 0.77 with the
// robot-level ρ fitted at λ = 0.99). Tolerances: the output ratio has a relative sd ≤ 3 % (as
// above), so (0.6, 0.9) around 0.77 is > 4 sd either side; the free fraction averages 200 robots
// over 2,500 s with contacts of about 4 s (sd well under 0.01), and the two predictions differ by
// about 0.1 here (measured 0.468; e^(−x) 0.480, 1/(1 + x) 0.577), so "within 0.03 of e^(−x) and
// nearer to it than to 1/(1 + x)" is several sd from either side. The ratio's bounds say only
// that the CTMC overestimates (at λ = 2 the ratio is 0.85, inside the 20 % above); the free
// fraction is what tells the two regimes apart.
TEST(PhysicsThroughputBeyondTheCtmc, AtFourPerSquareMetreOverlappingContactsPutTheOutputBelowTheCtmc) {
  const Point& fit = simulate(lambda_fit);
  const Point& beyond = simulate(lambda_beyond);
  const WorldParams p = testing::throughput_curve(robots, lambda_beyond);
  const double ratio = beyond.output / ctmc_output(p, lambda_beyond, fit.rho_robot);
  const double independent = std::exp(-beyond.contact_load);
  const double one_at_a_time = 1.0 / (1.0 + beyond.contact_load);
  RecordProperty("ratio", std::to_string(ratio));
  RecordProperty("free_fraction", std::to_string(beyond.free_fraction));
  RecordProperty("free_fraction_independent_contacts", std::to_string(independent));
  RecordProperty("free_fraction_one_at_a_time", std::to_string(one_at_a_time));
  ASSERT_GT(beyond.deliveries, 1500.0);
  EXPECT_GT(ratio, 0.6);
  EXPECT_LT(ratio, 0.9) << "the CTMC's curve no longer overestimates the output at λ = 4";
  EXPECT_NEAR(beyond.free_fraction, independent, 0.03);
  EXPECT_LT(std::abs(beyond.free_fraction - independent), std::abs(beyond.free_fraction - one_at_a_time));
}

TEST(PhysicsThroughputCurve, OutputGrowsSubLinearlyFromTwoToFourRobotsPerSquareMetre) {
  // The paper's qualitative claim (Fig. 3): T(λ)λ still grows, but less than proportionally.
  // Both margins are > 10 sd of the ratio (relative sd of each output ≤ 3 %).
  const Point& two = simulate(2.0);
  const Point& four = simulate(lambda_beyond);
  const WorldParams p = testing::throughput_curve(robots, lambda_beyond);
  RecordProperty("output_lambda_2", std::to_string(two.output));
  RecordProperty("output_lambda_4", std::to_string(four.output));
  RecordProperty("ctmc_output_lambda_4",
                 std::to_string(ctmc_output(p, lambda_beyond, simulate(lambda_fit).rho_robot)));
  RecordProperty("ratio_lambda_4",
                 std::to_string(four.output / ctmc_output(p, lambda_beyond, simulate(lambda_fit).rho_robot)));
  EXPECT_GT(four.output, 1.1 * two.output);
  EXPECT_LT(four.output, 1.7 * two.output);
}

}  // namespace
}  // namespace retreat::physics
