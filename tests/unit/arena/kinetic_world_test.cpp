// The kinetic world: Poisson encounters and the CTMC without positions.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

constexpr double pi = 3.14159265358979323846;

WorldParams kinetic(std::uint32_t robots, double area) {
  WorldParams p;
  p.encounter_model = EncounterModel::kinetic;
  p.shape = DomainShape::rectangle;
  p.width = std::sqrt(area);
  p.height = p.width;
  p.robots_inside = robots;
  p.robots_waiting = 0;
  p.lambda_in = 0.0;
  p.tick_dt = 0.1;
  p.physics_dt = 0.1;
  p.rho = 0.3;
  p.seed = 4;
  return p;
}

struct Summary {
  double omega_c = 0.0;                  // formula rate [1/s]
  double onset_rate = 0.0;               // measured onsets per robot per second
  std::vector<double> contact_fraction;  // per robot
  std::vector<double> delivery_rate;     // per robot [1/s]
};

/// 1000 robots, λ = 1, 2000 s: one shared run per process.
const Summary& summary() {
  static const Summary s = [] {
    Summary r;
    const std::uint32_t n = 1000;
    const WorldParams p = kinetic(n, 1000.0);
    const double duration = 2000.0;
    r.omega_c = 4.0 * p.delta * (4.0 / pi) * p.v * (n - 1) / 1000.0;
    auto world = make_world(p);
    for (long k = 0; k < std::lround(duration / p.tick_dt); ++k) {
      world->step_tick();
    }
    r.onset_rate = static_cast<double>(world->telemetry().onsets) / (n * duration);
    for (RobotId id = 0; id < n; ++id) {
      const RobotStats& st = world->robot_stats(id);
      const double total =
          st.state_time[0] + st.state_time[1] + st.state_time[2] + st.state_time[3];
      r.contact_fraction.push_back((st.state_time[2] + st.state_time[3]) / total);
      r.delivery_rate.push_back(static_cast<double>(st.deliveries) / duration);
    }
    return r;
  }();
  return s;
}

/// Mean and standard error of the mean of independent per-robot values.
std::pair<double, double> mean_and_se(const std::vector<double>& x) {
  double m = 0.0;
  for (const double v : x) {
    m += v;
  }
  m /= static_cast<double>(x.size());
  double ss = 0.0;
  for (const double v : x) {
    ss += (v - m) * (v - m);
  }
  return {m, std::sqrt(ss / static_cast<double>(x.size() - 1) / static_cast<double>(x.size()))};
}

TEST(PhysicsKineticWorld, OnsetRateMatchesTheSweptAreaFormula) {
  // Total onsets are Poisson with mean N·Ω_c·T ≈ 1.0e5: relative sd 0.31 %. Tolerance 1.6 %
  // = 5 sd (false failure ≈ 6e-7).
  const Summary& s = summary();
  RecordProperty("measured", std::to_string(s.onset_rate));
  RecordProperty("formula", std::to_string(s.omega_c));
  EXPECT_NEAR(s.onset_rate / s.omega_c, 1.0, 0.016);
}

TEST(PhysicsKineticWorld, ContactFractionMatchesTheCtmc) {
  // π_fc + π_lc = (Ω_c/ρ)/(1 + Ω_c/ρ). Robots of the kinetic world are independent given N, so
  // the per-robot fractions are iid; tolerance 5 standard errors (false failure ≈ 6e-7).
  const Summary& s = summary();
  const double x = s.omega_c / 0.3;
  const double expected = x / (1.0 + x);
  const auto [m, se] = mean_and_se(s.contact_fraction);
  RecordProperty("measured", std::to_string(m));
  RecordProperty("ctmc", std::to_string(expected));
  EXPECT_NEAR(m, expected, 5.0 * se);
  EXPECT_LT(se, 0.01 * expected);  // the test has power: 5 se < 5 % of the value
}

TEST(PhysicsKineticWorld, DeliveryRateMatchesTheCtmcThroughput) {
  // T = 2δv·(λ_pλ_d/(λ_p+λ_d))/(1 + Ω_c/ρ); per-robot delivery rates are iid: 5 standard errors.
  const Summary& s = summary();
  const WorldParams p = kinetic(1000, 1000.0);
  const double harmonic = p.lambda_p * p.lambda_d / (p.lambda_p + p.lambda_d);
  const double expected = 2.0 * p.delta * p.v * harmonic / (1.0 + s.omega_c / p.rho);
  const auto [m, se] = mean_and_se(s.delivery_rate);
  RecordProperty("measured", std::to_string(m));
  RecordProperty("ctmc", std::to_string(expected));
  EXPECT_NEAR(m, expected, 5.0 * se);
  EXPECT_LT(se, 0.02 * expected);
}

TEST(PhysicsKineticWorld, RetreatingRobotsKeepMeetingOthersUntilTheyDepart) {
  WorldParams p = kinetic(200, 200.0);
  auto world = make_world(p);
  for (RobotId id = 0; id < 100; ++id) {
    ASSERT_EQ(world->command_retreat(id), CommandVerdict::accepted);
  }
  // Drive-out time: mean distance to the boundary of a 14.1 m square (side/6 = 2.36 m) / v.
  const double drive_out = std::sqrt(200.0) / 6.0 / p.v;
  std::uint64_t onsets_while_retreating = 0;
  for (long k = 0; k < std::lround((drive_out + 1.0) / p.tick_dt); ++k) {
    world->step_tick();
    for (const RobotFrame& f : world->frames()) {
      if (f.id < 100 && f.phase == Phase::retreating) {
        onsets_while_retreating += f.new_onsets;
      }
    }
  }
  // Expected ≈ 100 robots × Ω_c (0.05/s) × 23.6 s ≈ 118; Poisson, so > 50 fails w.p. < 1e-10.
  EXPECT_GT(onsets_while_retreating, 50u);
  for (RobotId id = 0; id < 100; ++id) {
    const RobotStats& st = world->robot_stats(id);
    ASSERT_EQ(st.phase, Phase::departed);
    // The midpoint quadrature of the mean distance is accurate to < 1 %.
    EXPECT_NEAR(st.departed_at, drive_out, 0.01 * drive_out);
  }
  EXPECT_EQ(world->telemetry().inside, 100u);
  EXPECT_EQ(world->telemetry().departed, 100u);
}

TEST(PhysicsKineticWorld, StepsAHundredThousandRobots) {
  WorldParams p = kinetic(100000, 100000.0);
  auto world = make_world(p);
  for (int k = 0; k < 20; ++k) {
    world->step_tick();
  }
  const Telemetry t = world->telemetry();
  EXPECT_EQ(t.inside, 100000u);
  EXPECT_EQ(world->frames().size(), 100000u);
  EXPECT_GT(t.onsets, 0u);
  EXPECT_TRUE(world->poses().robots.empty());
}

}  // namespace
}  // namespace retreat::physics
