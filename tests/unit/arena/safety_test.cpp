// Barrier certificates keep robots apart and inside, at high density, with robots entering
// and retreating through the boundary.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "retreat/physics/domain.hpp"
#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

struct SafetyReport {
  long robot_steps = 0;
  double min_separation = 1e9;
  double max_footprint_overshoot = -1e9;  // max over walking robots of sd(centre) + r [m]
  bool center_left_domain = false;
  std::uint64_t departed = 0;
  std::uint64_t entered = 0;
};

/// Steps @p p (tick = physics step, so that every step is inspected) for @p steps steps,
/// commanding a retreat every @p retreat_every steps, and checks all pairs and the boundary
/// after every step with an independent brute-force pass over poses().
SafetyReport run(const WorldParams& p, int steps, int retreat_every) {
  SafetyReport report;
  const Domain domain = p.shape == DomainShape::ellipse ? Domain::ellipse(p.semi_axis_x, p.semi_axis_y)
                                             : Domain::rectangle(p.width, p.height);
  auto world = make_world(p);
  RobotId next_to_retreat = 0;
  for (int s = 1; s <= steps; ++s) {
    if (s % retreat_every == 0) {
      while (next_to_retreat < world->robot_count() &&
             world->command_retreat(next_to_retreat) != CommandVerdict::accepted) {
        ++next_to_retreat;
      }
    }
    world->step_tick();
    const Poses poses = world->poses();
    report.robot_steps += static_cast<long>(poses.robots.size());
    for (std::size_t i = 0; i < poses.robots.size(); ++i) {
      const RobotPose& a = poses.robots[i];
      const Vec2 pa(a.x, a.y);
      for (std::size_t j = i + 1; j < poses.robots.size(); ++j) {
        const RobotPose& b = poses.robots[j];
        report.min_separation = std::min(report.min_separation, std::hypot(a.x - b.x, a.y - b.y));
      }
      if (a.phase == Phase::inside && !a.entering) {
        const double sd = domain.signed_distance(pa);
        report.max_footprint_overshoot =
            std::max(report.max_footprint_overshoot, sd + p.robot_radius);
        report.center_left_domain = report.center_left_domain || sd > 0.0;
      }
    }
  }
  const Telemetry t = world->telemetry();
  report.departed = t.departed;
  // Endless queue: each entry created one new id.
  report.entered = world->robot_count() - p.robots_inside - p.robots_waiting;
  return report;
}

WorldParams dense(const std::string& shape) {
  WorldParams p;  // Robotarium defaults: v = 0.1, γ = 10⁴, D_s = 0.13, dt = 0.01
  p.shape = *value_of<DomainShape>(shape);
  p.semi_axis_x = 1.6;
  p.semi_axis_y = 1.0;
  p.width = 3.0;
  p.height = 2.0;
  p.tick_dt = p.physics_dt;
  p.queue = QueueKind::endless;
  p.robots_waiting = 2;
  p.lambda_in = 0.2;  // about one entry per 1.0–1.2 s
  p.tumble_rate = 0.2;
  p.seed = 77;
  // 12 robots/m²: the safety discs (diameter D_s) cover 16 % of D, robots meet constantly.
  const double area = shape == "ellipse" ? 3.14159265358979323846 * 1.6 * 1.0 : 6.0;
  p.robots_inside = static_cast<std::uint32_t>(12.0 * area);
  return p;
}

// Discretisation margins. Centres: none. The safety half-constraints act on v only, and forward
// Euler moves a centre by exactly v·e·dt, so h_c(t + dt) ≥ h_c(t)/2 > 0 holds exactly
// (barrier_certificate.hpp); only rounding (1e-12 m) is allowed. Footprint: the boundary
// constraint acts on the projected point q, which Euler moves by u·dt plus at most
// l·(ω_max·dt)²/2 per step, and a curvature term of the same order; the barrier n·u ≤ α·c pulls
// q back at rate α, so the overshoot settles below twice l·(ω_max·dt)²/2 / (α·dt).
// Defaults: 2 · 2.6e-5 / 0.3 = 1.7e-4 m; the fast case (ω_max·dt = 0.31): 7.8e-3 m.
double footprint_margin(const WorldParams& p) {
  const double drift = p.projection_distance * std::pow(p.max_turn_rate * p.physics_dt, 2) / 2.0;
  return 2.0 * drift / (p.boundary_gain * p.physics_dt);
}

TEST(PhysicsSafety, NoTwoRobotsEverComeCloserThanTheSafetyDistanceInAnEllipse) {
  const WorldParams p = dense("ellipse");
  const SafetyReport r = run(p, 3000, 150);
  ASSERT_GE(r.robot_steps, 100000);
  EXPECT_GE(r.min_separation, p.safety_distance - 1e-12);
  RecordProperty("min_separation_m", std::to_string(r.min_separation));
}

TEST(PhysicsSafety, NoTwoRobotsEverComeCloserThanTheSafetyDistanceInARectangle) {
  const WorldParams p = dense("rectangle");
  const SafetyReport r = run(p, 3000, 150);
  ASSERT_GE(r.robot_steps, 100000);
  EXPECT_GE(r.min_separation, p.safety_distance - 1e-12);
}

TEST(PhysicsSafety, WalkingRobotsKeepTheirFootprintInsideTheDomain) {
  for (const std::string shape : {"ellipse", "rectangle"}) {
    const WorldParams p = dense(shape);
    const SafetyReport r = run(p, 3000, 150);
    EXPECT_FALSE(r.center_left_domain) << shape;
    EXPECT_LE(r.max_footprint_overshoot, footprint_margin(p)) << shape;
    RecordProperty("max_footprint_overshoot_m_" + shape, std::to_string(r.max_footprint_overshoot));
  }
}

TEST(PhysicsSafety, RobotsEnterAndRetreatThroughTheBoundaryDuringTheDenseRun) {
  // 20 retreat commands in 30 s; robots deep inside a 12/m² crowd take 10–20 s to get out.
  const SafetyReport r = run(dense("ellipse"), 3000, 150);
  RecordProperty("departed", std::to_string(r.departed));
  RecordProperty("entered", std::to_string(r.entered));
  EXPECT_GE(r.departed, 5u);
  EXPECT_GE(r.entered, 5u);
}

TEST(PhysicsSafety, FastRobotsWithAStiffBarrierStayApartToo) {
  WorldParams p = dense("rectangle");
  p.v = 1.0;
  p.max_speed = 1.0;
  p.delta = 0.11;
  p.max_turn_rate = 31.25;
  p.gamma = 1e5;
  p.boundary_gain = 50.0;
  p.unblock_time = 0.2;
  p.tumble_rate = 2.0;
  p.lambda_in = 2.0;
  const SafetyReport r = run(p, 3000, 150);
  EXPECT_GE(r.min_separation, p.safety_distance - 1e-12);
  EXPECT_FALSE(r.center_left_domain);
  EXPECT_LE(r.max_footprint_overshoot, footprint_margin(p));
}

}  // namespace
}  // namespace retreat::physics
