// The physical world reproduces the paper's encounter model (MODEL.md §2, §6): λ = 0.99,
// δ = 0.11, v = 1, barrier certificates.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "paper_setups.hpp"
#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

constexpr std::uint32_t robots = 200;
constexpr double lambda = 0.99;
constexpr double warm_up = 5.0;     // s: lets the placement's correlations wash out
constexpr double duration = 100.0;  // s

struct Measurements {
  double formula_rate = 0.0;   // Ω_c = c(N − 1)/|D| [1/s]
  double measured_rate = 0.0;  // onsets per robot per second
  double total_onsets = 0.0;
  std::vector<double> intervals;       // per-robot inter-onset times [s]
  std::vector<double> pair_durations;  // [s]
  std::vector<double> episode_durations;
  double dt = 0.0;
};

/// One simulation shared by the tests of this file (each ctest process runs it once).
const Measurements& measurements() {
  static const Measurements result = [] {
    Measurements r;
    const WorldParams p = testing::encounter_validation(robots, lambda);
    r.dt = p.tick_dt;
    const double area = p.width * p.height;
    r.formula_rate = testing::swept_area_rate(p) * (robots - 1) / area;
    auto world = make_world(p);
    for (long k = 0; k < std::lround(warm_up / p.tick_dt); ++k) {
      world->step_tick();
    }
    world->take_contact_records();
    std::vector<double> last(robots, -1.0);
    for (long k = 0; k < std::lround(duration / p.tick_dt); ++k) {
      world->step_tick();
      for (const RobotFrame& f : world->frames()) {
        for (std::uint32_t n = 0; n < f.new_onsets; ++n) {
          if (last[f.id] >= 0.0) {
            r.intervals.push_back(f.time - last[f.id]);
          }
          last[f.id] = f.time;
          r.total_onsets += 1.0;
        }
      }
      for (const ContactRecord& c : world->take_contact_records()) {
        (c.other == no_robot ? r.episode_durations : r.pair_durations).push_back(c.end - c.start);
      }
    }
    r.measured_rate = r.total_onsets / (robots * duration);
    return r;
  }();
  return result;
}

double mean(const std::vector<double>& x) {
  double s = 0.0;
  for (const double v : x) {
    s += v;
  }
  return s / static_cast<double>(x.size());
}

TEST(PhysicsEncounterModel, OnsetRatePerRobotMatchesTheSweptAreaFormula) {
  // Each encounter is one onset for each of its two robots, so the onset count is twice a
  // (near-)Poisson count of pair events: relative sd √(2/onsets) ≈ 1.35 % at ~11 000 onsets.
  // Tolerance 5 % = 3.7 sd (false failure ≈ 2e-4), which also covers the O(1 %) boundary
  // effects of a finite square (robots near the wall have fewer neighbours but the walk region
  // is 2 % smaller than |D|).
  const Measurements& r = measurements();
  RecordProperty("measured_onset_rate", std::to_string(r.measured_rate));
  RecordProperty("formula_onset_rate", std::to_string(r.formula_rate));
  RecordProperty("ratio", std::to_string(r.measured_rate / r.formula_rate));
  ASSERT_GT(r.total_onsets, 8000.0);
  EXPECT_NEAR(r.measured_rate / r.formula_rate, 1.0, 0.05);
}

TEST(PhysicsEncounterModel, InterEncounterTimesAreExponentialWithTheFormulaRate) {
  // One-sample Kolmogorov–Smirnov test against Exp(Ω_c) with Ω_c from the formula (not fitted).
  // Critical value at α = 0.001: 1.95/√n_eff. n_eff = n/2 because each encounter appears in two
  // robots' sequences (conservative). Onset times are sampled every dt = 0.01 s, which moves
  // the empirical CDF by at most Ω_c·dt = 0.0055; that bound is added to the threshold.
  const Measurements& r = measurements();
  std::vector<double> x = r.intervals;
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = 1.0 - std::exp(-r.formula_rate * x[i]);
    d = std::max({d, std::abs(f - static_cast<double>(i) / n),
                  std::abs(f - static_cast<double>(i + 1) / n)});
  }
  const double threshold = 1.95 / std::sqrt(n / 2.0) + r.formula_rate * r.dt;
  RecordProperty("ks_statistic", std::to_string(d));
  RecordProperty("ks_threshold", std::to_string(threshold));
  RecordProperty("intervals", std::to_string(x.size()));
  ASSERT_GT(x.size(), 5000u);
  EXPECT_LT(d, threshold);
}

TEST(PhysicsEncounterModel, ContactDurationsYieldAFittedRho) {
  // ρ is the maximum-likelihood rate of an exponential fit, 1 / mean duration. Two readings:
  // per pair (the time two robots stay within 2δ) and per robot (the time until a robot has no
  // one within 2δ: the CTMC's fc/lc sojourn, MODEL.md §3). The paper reports ρ = 2.44.
  const Measurements& r = measurements();
  ASSERT_GT(r.pair_durations.size(), 2000u);
  ASSERT_GT(r.episode_durations.size(), 2000u);
  const double rho_pair = 1.0 / mean(r.pair_durations);
  const double rho_robot = 1.0 / mean(r.episode_durations);
  RecordProperty("rho_pair", std::to_string(rho_pair));
  RecordProperty("rho_robot", std::to_string(rho_robot));
  RecordProperty("rho_paper", "2.44");
  // Coefficient of variation of the durations: 1 for an exponential.
  double ss = 0.0;
  for (const double v : r.episode_durations) {
    ss += (v * rho_robot - 1.0) * (v * rho_robot - 1.0);
  }
  RecordProperty("robot_duration_cv",
                 std::to_string(std::sqrt(ss / static_cast<double>(r.episode_durations.size()))));
  EXPECT_GT(rho_pair, 0.0);
  EXPECT_GE(rho_pair, rho_robot);  // a robot's contact lasts at least as long as each of its pairs
}

}  // namespace
}  // namespace retreat::physics
