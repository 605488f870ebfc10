// Domains, unicycle kinematics, the generator and the neighbour grid.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "retreat/physics/domain.hpp"
#include "retreat/physics/ellipse_root.hpp"
#include "retreat/physics/neighbour_grid.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/physics/unicycle.hpp"

namespace retreat::physics {
namespace {

constexpr double pi = 3.14159265358979323846;

TEST(PhysicsDomain, EllipseAreaAndPerimeterMatchClosedForms) {
  const Domain d = Domain::ellipse(1.2, 0.8);
  EXPECT_NEAR(d.area(), pi * 1.2 * 0.8, 1e-12);
  // Ramanujan's second approximation is accurate to ~1e-7 relative at this eccentricity.
  const double h = std::pow((1.2 - 0.8) / (1.2 + 0.8), 2);
  const double ramanujan = pi * 2.0 * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
  EXPECT_NEAR(d.perimeter(), ramanujan, 1e-6);
}

TEST(PhysicsDomain, RectangleAreaPerimeterAndInsetAreaAreExact) {
  const Domain d = Domain::rectangle(3.2, 2.0);
  EXPECT_DOUBLE_EQ(d.area(), 6.4);
  EXPECT_DOUBLE_EQ(d.perimeter(), 10.4);
  EXPECT_DOUBLE_EQ(d.inset_area(0.1), 3.0 * 1.8);
  EXPECT_DOUBLE_EQ(d.inset_area(1.5), 0.0);
}

TEST(PhysicsDomain, EllipseInsetAreaMatchesACountOfInsidePoints) {
  const Domain d = Domain::ellipse(1.2, 0.8);
  for (const double inset : {0.1, 0.5, 0.7}) {  // 0.7 is past the least curvature radius 0.53
    constexpr int n = 600;
    int count = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const Vec2 p(-1.2 + 2.4 * (i + 0.5) / n, -0.8 + 1.6 * (j + 0.5) / n);
        count += d.signed_distance(p) <= -inset ? 1 : 0;
      }
    }
    const double counted = count * (2.4 / n) * (1.6 / n);
    // Midpoint counting error is of order perimeter × cell size (0.004 m): < 0.02 m².
    EXPECT_NEAR(d.inset_area(inset), counted, 0.02) << "inset " << inset;
  }
}

TEST(PhysicsDomain, ContainsAgreesWithTheSignOfTheSignedDistance) {
  Rng rng(7);
  for (const Domain& d :
       {Domain::ellipse(1.2, 0.8), Domain::ellipse(0.5, 2.0), Domain::rectangle(3.2, 2.0)}) {
    for (int k = 0; k < 2000; ++k) {
      const Vec2 p(rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5));
      EXPECT_EQ(d.contains(p), d.signed_distance(p) <= 0.0) << p.transpose();
    }
  }
}

TEST(PhysicsDomain, NearestBoundaryPointIsTheClosestOfADenseBoundarySample) {
  Rng rng(11);
  for (const Domain& d :
       {Domain::ellipse(1.2, 0.8), Domain::ellipse(0.5, 2.0), Domain::rectangle(3.2, 2.0)}) {
    // 20 000 boundary points, spaced ≤ 0.6 mm: the brute-force distance is within 1e-3 m.
    std::vector<Vec2> boundary;
    for (int k = 0; k < 20000; ++k) {
      boundary.push_back(d.sample_boundary(rng).point);
    }
    for (int k = 0; k < 200; ++k) {
      const Vec2 p(rng.uniform(-2.2, 2.2), rng.uniform(-2.2, 2.2));
      const BoundaryPoint b = d.nearest_boundary_point(p);
      double brute = 1e9;
      for (const Vec2& q : boundary) {
        brute = std::min(brute, (q - p).norm());
      }
      EXPECT_NEAR(std::abs(b.signed_distance), brute, 1e-3) << p.transpose();
      EXPECT_LE(std::abs(b.signed_distance), brute + 1e-12) << p.transpose();
      EXPECT_NEAR((b.point - p).norm(), std::abs(b.signed_distance), 1e-12);
      EXPECT_NEAR(b.outward_normal.norm(), 1.0, 1e-12);
      // The outward normal points from the boundary point away from D.
      EXPECT_FALSE(d.contains(b.point + 1e-6 * b.outward_normal)) << p.transpose();
    }
  }
}

// ellipse_root must return the bisection's own double (every physical trajectory depends on its
// last bit), wherever the point is: anywhere in and around the ellipse, within 10⁻¹⁵ … 10⁻¹ of
// its boundary (where the root is near 0 and the most midpoints fall near it), near the axes,
// and for a circle, the arena's ellipse, a tall one and a needle (r0 = 1, 2.25, 16, 10⁴).
TEST(PhysicsEllipseRoot, IsTheBisectionsDoubleBitForBit) {
  Rng rng(29);
  std::uint64_t compared = 0;
  const auto expect_same = [&](double e0, double e1, double y0, double y1) {
    const double z0 = y0 / e0;
    const double z1 = y1 / e1;
    const double g = z0 * z0 + z1 * z1 - 1.0;
    const double r0 = (e0 / e1) * (e0 / e1);
    const double want = ellipse_root_by_bisection(r0, z0, z1, g);
    const double got = ellipse_root(r0, z0, z1, g);
    ++compared;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(want))
        << "e = (" << e0 << ", " << e1 << "), y = (" << y0 << ", " << y1 << "): " << got << " against " << want;
  };
  for (const auto& [e0, e1] : {std::pair{1.0, 1.0}, std::pair{1.2, 0.8}, std::pair{2.0, 0.5}, std::pair{1.0, 0.01}}) {
    for (int k = 0; k < 100000; ++k) {
      expect_same(e0, e1, rng.uniform(0.0, 1.5 * e0), rng.uniform(0.0, 1.5 * e1));
      const double t = rng.uniform(0.0, pi / 2.0);
      const double off = std::pow(10.0, -rng.uniform(1.0, 15.0)) * (rng.uniform() < 0.5 ? -1.0 : 1.0);
      expect_same(e0, e1, e0 * std::cos(t) * (1.0 + off), e1 * std::sin(t) * (1.0 + off));
      expect_same(e0, e1, rng.uniform(0.0, 1.5 * e0), e1 * std::pow(10.0, -rng.uniform(1.0, 12.0)));
      expect_same(e0, e1, e0 * std::pow(10.0, -rng.uniform(1.0, 12.0)), rng.uniform(0.0, 1.5 * e1));
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_EQ(compared, 1600000u);
}

TEST(PhysicsDomain, ClearanceLowerBoundNeverExceedsTheTrueClearance) {
  Rng rng(3);
  const Domain d = Domain::ellipse(1.2, 0.8);
  for (int k = 0; k < 5000; ++k) {
    const Vec2 p = d.sample_uniform(rng);
    EXPECT_LE(d.clearance_lower_bound(p), -d.signed_distance(p) + 1e-12);
  }
}

TEST(PhysicsDomain, UniformSamplesHaveTheMomentsOfTheUniformDistribution) {
  // E[x²] = a²/4 for the ellipse; with 40 000 samples the standard error of the mean of x² is
  // sd(x²)/200 ≈ 0.0016 (a = 1.2); 5 standard errors: false failure ≈ 6e-7.
  Rng rng(5);
  const Domain d = Domain::ellipse(1.2, 0.8);
  double sx2 = 0.0;
  double sy2 = 0.0;
  constexpr int n = 40000;
  for (int k = 0; k < n; ++k) {
    const Vec2 p = d.sample_uniform(rng);
    ASSERT_TRUE(d.contains(p));
    sx2 += p.x() * p.x();
    sy2 += p.y() * p.y();
  }
  EXPECT_NEAR(sx2 / n, 1.2 * 1.2 / 4.0, 0.008);
  EXPECT_NEAR(sy2 / n, 0.8 * 0.8 / 4.0, 0.004);
}

TEST(PhysicsDomain, BoundarySamplesAreUniformByArcLength) {
  // Fraction of ellipse boundary samples with |x| > a/2, against the arc-length fraction
  // computed by quadrature. Binomial, n = 40 000: sd ≤ 0.0025; tolerance 0.0125 = 5 sd.
  Rng rng(9);
  const double a = 2.0;
  const double b = 0.5;
  const Domain d = Domain::ellipse(a, b);
  int far = 0;
  constexpr int n = 40000;
  for (int k = 0; k < n; ++k) {
    const BoundaryPoint bp = d.sample_boundary(rng);
    EXPECT_NEAR(std::pow(bp.point.x() / a, 2) + std::pow(bp.point.y() / b, 2), 1.0, 1e-12);
    far += std::abs(bp.point.x()) > a / 2 ? 1 : 0;
  }
  double arc_far = 0.0;
  constexpr int m = 100000;
  for (int k = 0; k < m; ++k) {
    const double t = 2.0 * pi * (k + 0.5) / m;
    const double speed = std::hypot(a * std::sin(t), b * std::cos(t));
    arc_far += std::abs(a * std::cos(t)) > a / 2 ? speed : 0.0;
  }
  arc_far *= 2.0 * pi / m / d.perimeter();
  EXPECT_NEAR(static_cast<double>(far) / n, arc_far, 0.0125);
}

TEST(PhysicsUnicycle, ProjectedPointVelocityMapsToSpeedAndTurnRateAndBack) {
  Rng rng(1);
  for (int k = 0; k < 100; ++k) {
    const double theta = rng.angle();
    const Vec2 e = heading(theta);
    const Vec2 u(rng.uniform(-1, 1), rng.uniform(-1, 1));
    const UnicycleCommand c = to_unicycle_command(e, u, 0.04);
    EXPECT_NEAR(c.v, e.dot(u), 1e-15);
    EXPECT_NEAR((projected_velocity(e, c, 0.04) - u).norm(), 0.0, 1e-14);
  }
}

TEST(PhysicsUnicycle, ForwardEulerMovesTheCentreAlongTheOldHeading) {
  const Pose start{Vec2(1.0, 2.0), pi / 2};
  const Pose next = integrate_euler(start, {0.1, 1.0}, 0.5);
  EXPECT_NEAR(next.position.x(), 1.0, 1e-15);
  EXPECT_NEAR(next.position.y(), 2.05, 1e-15);
  EXPECT_NEAR(next.theta, pi / 2 + 0.5, 1e-15);
}

TEST(PhysicsUnicycle, HeadingsAreWrappedIntoMinusPiToPi) {
  EXPECT_NEAR(wrap_angle(3 * pi / 2), -pi / 2, 1e-15);
  EXPECT_NEAR(wrap_angle(-3 * pi / 2), pi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(wrap_angle(pi), pi);
  EXPECT_DOUBLE_EQ(wrap_angle(-pi), pi);
  const Pose p = integrate_euler({Vec2::Zero(), 3.0}, {0.0, 1.0}, 1.0);
  EXPECT_NEAR(p.theta, 4.0 - 2 * pi, 1e-15);
}

TEST(PhysicsUnicycle, CommandsAreClampedToTheLimits) {
  const UnicycleCommand c = clamp_command({0.5, -9.0}, 0.2, 3.6);
  EXPECT_DOUBLE_EQ(c.v, 0.2);
  EXPECT_DOUBLE_EQ(c.omega, -3.6);
}

TEST(PhysicsRng, SameSeedGivesTheSameStreamAndDifferentSeedsDiffer) {
  Rng a(42);
  Rng b(42);
  Rng c(43);
  int same = 0;
  for (int k = 0; k < 100; ++k) {
    const auto x = a();
    EXPECT_EQ(x, b());
    same += x == c() ? 1 : 0;
  }
  EXPECT_EQ(same, 0);
}

TEST(PhysicsRng, ExponentialAndPoissonHaveTheRightMeans) {
  // n = 200 000: sd of the exponential mean = 0.5/√n·... = 0.0011 (rate 2); Poisson(3.7) mean
  // sd = √3.7/√n = 0.0043, Poisson(75) mean sd = 0.019; tolerances are 5 sd (false failure
  // ≈ 6e-7 each).
  Rng rng(2);
  constexpr int n = 200000;
  double exp_sum = 0.0;
  double small_sum = 0.0;
  double large_sum = 0.0;
  for (int k = 0; k < n; ++k) {
    exp_sum += rng.exponential(2.0);
    small_sum += static_cast<double>(rng.poisson(3.7));
    large_sum += static_cast<double>(rng.poisson(75.0));
  }
  EXPECT_NEAR(exp_sum / n, 0.5, 0.0056);
  EXPECT_NEAR(small_sum / n, 3.7, 0.022);
  EXPECT_NEAR(large_sum / n, 75.0, 0.097);
  EXPECT_EQ(rng.poisson(0.0), 0u);
  EXPECT_TRUE(std::isinf(rng.exponential(0.0)));
}

TEST(PhysicsNeighbourGrid, FindsExactlyThePairsABruteForceSearchFinds) {
  Rng rng(13);
  std::vector<Vec2> points;
  for (int k = 0; k < 3000; ++k) {
    // Some points outside the grid's rectangle: they are clamped into border cells.
    points.emplace_back(rng.uniform(-6, 6), rng.uniform(-4, 4));
  }
  const double radius = 0.3;
  NeighbourGrid grid(Vec2(-5, -3), Vec2(5, 3), radius);
  ASSERT_GE(grid.cell_size(), radius);
  grid.build(points);
  for (std::size_t i = 0; i < points.size(); i += 7) {
    std::vector<std::uint32_t> found;
    grid.for_each_candidate(points[i], [&](std::uint32_t j) {
      if (j != i && (points[j] - points[i]).norm() <= radius) {
        found.push_back(j);
      }
    });
    std::vector<std::uint32_t> brute;
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (j != i && (points[j] - points[i]).norm() <= radius) {
        brute.push_back(static_cast<std::uint32_t>(j));
      }
    }
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, brute) << "point " << i;
  }
}

TEST(PhysicsNeighbourGrid, EnlargesCellsRatherThanExceedingTheCellBudget) {
  const NeighbourGrid grid(Vec2(0, 0), Vec2(1000, 1000), 0.01, 10000);
  EXPECT_GE(grid.cell_size(), 10.0);
}

}  // namespace
}  // namespace retreat::physics
