// The exact barrier QP against brute force, and the certificate's constraints.

#include "retreat/physics/barrier_qp.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <vector>

#include "retreat/physics/barrier_certificate.hpp"
#include "retreat/core/rng.hpp"

namespace retreat::physics {
namespace {

bool feasible(const Vec2& u, const std::vector<HalfPlane>& c, double tol) {
  for (const HalfPlane& h : c) {
    if (h.a.dot(u) > h.b + tol) {
      return false;
    }
  }
  return true;
}

/// Vertex enumeration: the projection onto a polygon is û itself, the projection onto one edge
/// line, or a vertex (the intersection of two lines); take the closest feasible candidate.
/// Returns NaN if no candidate is feasible (empty polygon).
Vec2 brute_force(const Vec2& u_hat, const std::vector<HalfPlane>& c) {
  const double tol = 1e-9;
  std::vector<Vec2> candidates{u_hat};
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double aa = c[i].a.squaredNorm();
    candidates.push_back(u_hat - (c[i].a.dot(u_hat) - c[i].b) / aa * c[i].a);
    for (std::size_t j = i + 1; j < c.size(); ++j) {
      Eigen::Matrix2d m;
      m << c[i].a.transpose(), c[j].a.transpose();
      if (std::abs(m.determinant()) < 1e-12) {
        continue;
      }
      candidates.push_back(m.inverse() * Vec2(c[i].b, c[j].b));
    }
  }
  Vec2 best = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  double best_d = std::numeric_limits<double>::infinity();
  for (const Vec2& u : candidates) {
    if (feasible(u, c, tol) && (u - u_hat).squaredNorm() < best_d) {
      best_d = (u - u_hat).squaredNorm();
      best = u;
    }
  }
  return best;
}

std::vector<HalfPlane> relaxed(std::vector<HalfPlane> c) {
  for (HalfPlane& h : c) {
    h.b = std::max(h.b, 0.0);
  }
  return c;
}

TEST(PhysicsBarrierQp, MatchesVertexEnumerationOnRandomSmallProblems) {
  Rng rng(2024);
  int optimal = 0;
  int relaxed_count = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int m = 1 + static_cast<int>(rng.uniform() * 9);
    std::vector<HalfPlane> c;
    for (int k = 0; k < m; ++k) {
      const double angle = rng.angle();
      const double scale = rng.uniform(0.1, 3.0);
      c.push_back({scale * Vec2(std::cos(angle), std::sin(angle)), scale * rng.uniform(-0.3, 1.0)});
    }
    const Vec2 u_hat(rng.uniform(-2, 2), rng.uniform(-2, 2));
    const QpResult result = solve_barrier_qp(u_hat, c);
    const Vec2 exact = brute_force(u_hat, c);
    if (std::isnan(exact.x())) {
      // Empty polygon: the solver must report the relaxation and solve the relaxed problem.
      ASSERT_EQ(result.status, QpStatus::relaxed) << "trial " << trial;
      const Vec2 exact_relaxed = brute_force(u_hat, relaxed(c));
      EXPECT_NEAR((result.u - exact_relaxed).norm(), 0.0, 1e-7) << "trial " << trial;
      ++relaxed_count;
    } else {
      ASSERT_NE(result.status, QpStatus::relaxed) << "trial " << trial;
      EXPECT_TRUE(feasible(result.u, c, 1e-9)) << "trial " << trial;
      EXPECT_NEAR((result.u - exact).norm(), 0.0, 1e-7) << "trial " << trial;
      optimal += result.status == QpStatus::optimal ? 1 : 0;
    }
  }
  // Both branches must have been exercised substantially.
  EXPECT_GT(optimal, 5000);
  EXPECT_GT(relaxed_count, 500);
}

TEST(PhysicsBarrierQp, ReturnsTheDesiredVelocityWhenItIsFeasible) {
  const std::vector<HalfPlane> c{{Vec2(1, 0), 1.0}, {Vec2(0, 1), 1.0}};
  const QpResult r = solve_barrier_qp(Vec2(0.5, -3.0), c);
  EXPECT_EQ(r.status, QpStatus::unconstrained);
  EXPECT_EQ(r.u, Vec2(0.5, -3.0));
}

TEST(PhysicsBarrierQp, ProjectsOntoACornerWhenTwoConstraintsBind) {
  const std::vector<HalfPlane> c{{Vec2(1, 0), 1.0}, {Vec2(0, 1), 2.0}};
  const QpResult r = solve_barrier_qp(Vec2(3.0, 5.0), c);
  EXPECT_EQ(r.status, QpStatus::optimal);
  EXPECT_NEAR((r.u - Vec2(1.0, 2.0)).norm(), 0.0, 1e-15);
}

TEST(PhysicsBarrierQp, ContradictoryConstraintsRelaxToDoNotMakeThingsWorse) {
  // x ≤ −1 and −x ≤ −1 cannot both hold; relaxed: x ≤ 0 and −x ≤ 0, so x = 0.
  const std::vector<HalfPlane> c{{Vec2(1, 0), -1.0}, {Vec2(-1, 0), -1.0}};
  const QpResult r = solve_barrier_qp(Vec2(0.7, 0.3), c);
  EXPECT_EQ(r.status, QpStatus::relaxed);
  EXPECT_NEAR((r.u - Vec2(0.0, 0.3)).norm(), 0.0, 1e-15);
}

BarrierParams robotarium() {
  BarrierParams p;
  p.gamma = 1e4;
  p.safety_distance = 0.13;
  p.projection_distance = 0.04;
  p.boundary_gain = 30.0;
  p.max_speed = 0.2;
  p.max_turn_rate = 3.6;
  p.dt = 0.01;
  return p;
}

SensedBody body(const Vec2& p, double theta, double l) {
  const Vec2 e(std::cos(theta), std::sin(theta));
  return {p, e, p + l * e};
}

TEST(PhysicsBarrierCertificate, PairsBeyondTheInteractionRangeAddNoConstraint) {
  const BarrierCertificate cert(robotarium());
  Rng rng(8);
  for (int k = 0; k < 2000; ++k) {
    const SensedBody self = body(Vec2::Zero(), rng.angle(), 0.04);
    const double d = cert.interaction_range() * rng.uniform(1.0, 3.0);
    const double bearing = rng.angle();
    const SensedBody other =
        body(d * Vec2(std::cos(bearing), std::sin(bearing)), rng.angle(), 0.04);
    std::vector<HalfPlane> c;
    cert.add_neighbour(c, self, other);
    EXPECT_TRUE(c.empty()) << "distance " << d;
  }
}

TEST(PhysicsBarrierCertificate, HeadOnRobotsCannotCloseFasterThanTheBarrierAllows) {
  const BarrierCertificate cert(robotarium());
  // Centres 0.15 apart facing each other: h_c = 0.15² − 0.13²; robot 0 wants full speed ahead.
  const SensedBody self = body(Vec2::Zero(), 0.0, 0.04);
  const SensedBody other = body(Vec2(0.15, 0.0), 3.14159265358979323846, 0.04);
  std::vector<HalfPlane> c;
  cert.add_limits(c, self.e);
  cert.add_neighbour(c, self, other);
  const QpResult r = solve_barrier_qp(Vec2(0.1, 0.0), c);
  const UnicycleCommand command = cert.to_command(self, r.u);
  const double h = 0.15 * 0.15 - 0.13 * 0.13;
  // Safety half-constraint: 2·0.15·v ≤ B(h_c).
  EXPECT_LE(2.0 * 0.15 * command.v, cert.barrier_bound(h) + 1e-15);
  EXPECT_LT(command.v, 0.1);
}

}  // namespace
}  // namespace retreat::physics
