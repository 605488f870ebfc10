// The random walk's stationary density is uniform (chi-square on a grid).

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "retreat/physics/domain.hpp"
#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

struct Samples {
  std::vector<Vec2> centre;
  std::vector<Vec2> projected;
  double lag1_autocorrelation = 0.0;  // of the x coordinate of q, between successive samples
};

/// Thinning. Successive samples of one robot are `thin` = 60 s apart. With runs of v/rate = 1 m
/// in a 3 m × 2 m domain the walk mixes like a diffusion with D = v²/(2·rate) = 0.05 m²/s; its
/// slowest mode along x relaxes in L²/(π²D) ≈ 18 s, so the lag-1 autocorrelation at 60 s is
/// about e^(−60/18) ≈ 0.04 (measured 0.26 at 30 s, as this estimate predicts: 0.19). The test
/// measures it and requires < 0.1, where the variance of a cell count is inflated by at most
/// (1 + 0.1)/(1 − 0.1) = 1.22 over independent samples.
Samples sample(const WorldParams& p, int per_robot, double thin, double warm_up) {
  Samples s;
  auto world = make_world(p);
  const auto ticks_per_sample = static_cast<long>(std::lround(thin / p.tick_dt));
  for (long k = 0; k < static_cast<long>(std::lround(warm_up / p.tick_dt)); ++k) {
    world->step_tick();
  }
  std::vector<std::vector<double>> xs(p.robots_inside);
  for (int n = 0; n < per_robot; ++n) {
    for (long k = 0; k < ticks_per_sample; ++k) {
      world->step_tick();
    }
    for (const RobotPose& r : world->poses().robots) {
      const Vec2 centre(r.x, r.y);
      const Vec2 q = centre + p.projection_distance * Vec2(std::cos(r.theta), std::sin(r.theta));
      s.centre.push_back(centre);
      s.projected.push_back(q);
      xs[r.id].push_back(q.x());
    }
  }
  double num = 0.0;
  double den = 0.0;
  double mean = 0.0;
  std::size_t count = 0;
  for (const auto& x : xs) {
    for (const double v : x) {
      mean += v;
      ++count;
    }
  }
  mean /= static_cast<double>(count);
  for (const auto& x : xs) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      den += (x[i] - mean) * (x[i] - mean);
      if (i + 1 < x.size()) {
        num += (x[i] - mean) * (x[i + 1] - mean);
      }
    }
  }
  s.lag1_autocorrelation = num / den;
  return s;
}

/// Pearson's statistic for @p points over an nx × ny grid of the box [lo, hi]; the expected
/// probability of a cell is the fraction of its area inside @p region (a 60 × 60 midpoint
/// count), normalised. Cells expecting fewer than 20 samples are pooled into one bin.
/// Returns {chi2, degrees of freedom}.
std::pair<double, int> chi_square(const std::vector<Vec2>& points, const Vec2& lo, const Vec2& hi,
                                  int nx, int ny, const std::function<bool(const Vec2&)>& region) {
  const Vec2 cell((hi.x() - lo.x()) / nx, (hi.y() - lo.y()) / ny);
  std::vector<double> weight(static_cast<std::size_t>(nx * ny), 0.0);
  double total_weight = 0.0;
  constexpr int m = 60;
  for (int c = 0; c < nx * ny; ++c) {
    const Vec2 origin = lo + Vec2((c % nx) * cell.x(), (c / nx) * cell.y());
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) {
        if (region(origin + Vec2((i + 0.5) * cell.x() / m, (j + 0.5) * cell.y() / m))) {
          weight[static_cast<std::size_t>(c)] += 1.0;
        }
      }
    }
    total_weight += weight[static_cast<std::size_t>(c)];
  }
  std::vector<double> observed(weight.size(), 0.0);
  double in_region = 0.0;
  for (const Vec2& p : points) {
    const int cx = static_cast<int>(std::floor((p.x() - lo.x()) / cell.x()));
    const int cy = static_cast<int>(std::floor((p.y() - lo.y()) / cell.y()));
    if (cx < 0 || cy < 0 || cx >= nx || cy >= ny || !region(p)) {
      continue;
    }
    observed[static_cast<std::size_t>(cy * nx + cx)] += 1.0;
    in_region += 1.0;
  }
  double chi2 = 0.0;
  int bins = 0;
  double pooled_observed = 0.0;
  double pooled_expected = 0.0;
  for (std::size_t c = 0; c < weight.size(); ++c) {
    const double expected = in_region * weight[c] / total_weight;
    if (expected < 20.0) {
      pooled_observed += observed[c];
      pooled_expected += expected;
      continue;
    }
    chi2 += (observed[c] - expected) * (observed[c] - expected) / expected;
    ++bins;
  }
  if (pooled_expected >= 5.0) {
    chi2 +=
        (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
    ++bins;
  }
  return {chi2, bins - 1};
}

/// Upper 0.1 % point of χ²_k by the Wilson–Hilferty approximation (accurate to < 1 % for
/// k ≥ 10): k·(1 − 2/(9k) + 3.0902·√(2/(9k)))³.
double chi2_critical_0001(int k) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + 3.0902 * std::sqrt(a), 3);
}

WorldParams walk_world(const std::string& shape) {
  WorldParams p;  // Robotarium defaults, 4 robots
  p.shape = *value_of<DomainShape>(shape);
  p.semi_axis_x = 1.5;
  p.semi_axis_y = 1.0;
  p.width = 3.0;
  p.height = 2.0;
  p.robots_inside = 4;
  p.robots_waiting = 0;
  p.lambda_in = 0.0;
  p.physics_dt = 0.03;  // 3 mm per step
  p.tick_dt = 0.03;
  p.tumble_rate = 0.1;
  p.seed = 31;
  return p;
}

// Each test: 4 robots × 600 samples = 2400 samples, 60 s apart, after a 60 s warm-up. Under
// uniformity Pearson's statistic is χ² with (bins − 1) degrees of freedom; the threshold is its
// upper 0.1 % point, so a correct walk fails with probability ≈ 0.001 (a little more with the
// residual autocorrelation allowed above).

TEST(PhysicsRandomWalk, ProjectedPointIsUniformOverTheWalkRegionOfARectangle) {
  const WorldParams p = walk_world("rectangle");
  const Domain d = Domain::rectangle(p.width, p.height);
  const double inset = walk_inset(p);
  const Samples s = sample(p, 600, 60.0, 60.0);
  EXPECT_LT(std::abs(s.lag1_autocorrelation), 0.1);
  const Vec2 hi(1.5 - inset, 1.0 - inset);
  const auto [chi2, dof] = chi_square(
      s.projected, -hi, hi, 6, 4, [&](const Vec2& q) { return d.signed_distance(q) <= -inset; });
  RecordProperty("chi2", std::to_string(chi2));
  RecordProperty("dof", std::to_string(dof));
  RecordProperty("lag1_autocorrelation", std::to_string(s.lag1_autocorrelation));
  EXPECT_EQ(dof, 23);
  EXPECT_LT(chi2, chi2_critical_0001(dof));
}

TEST(PhysicsRandomWalk, ProjectedPointIsUniformOverTheWalkRegionOfAnEllipse) {
  const WorldParams p = walk_world("ellipse");
  const Domain d = Domain::ellipse(p.semi_axis_x, p.semi_axis_y);
  const double inset = walk_inset(p);
  const Samples s = sample(p, 600, 60.0, 60.0);
  EXPECT_LT(std::abs(s.lag1_autocorrelation), 0.1);
  const Vec2 hi(1.5, 1.0);
  const auto [chi2, dof] = chi_square(s.projected, -hi, hi, 8, 6, [&](const Vec2& q) {
    return d.clearance_lower_bound(q) >= inset || d.signed_distance(q) <= -inset;
  });
  RecordProperty("chi2", std::to_string(chi2));
  RecordProperty("dof", std::to_string(dof));
  EXPECT_GE(dof, 20);
  EXPECT_LT(chi2, chi2_critical_0001(dof));
}

TEST(PhysicsRandomWalk, RobotCentresAreUniformAwayFromTheBoundary) {
  // Within l of the walk region's edge a centre trails its projected point, so the centres are
  // tested on the region at least walk_inset + l inside ∂D, conditionally on being there.
  const WorldParams p = walk_world("rectangle");
  const double inner = walk_inset(p) + p.projection_distance;
  const Samples s = sample(p, 600, 60.0, 60.0);
  const Vec2 hi(1.5 - inner, 1.0 - inner);
  const auto [chi2, dof] = chi_square(s.centre, -hi, hi, 5, 3, [&](const Vec2& c) {
    return std::abs(c.x()) <= hi.x() && std::abs(c.y()) <= hi.y();
  });
  RecordProperty("chi2", std::to_string(chi2));
  EXPECT_EQ(dof, 14);
  EXPECT_LT(chi2, chi2_critical_0001(dof));
}

}  // namespace
}  // namespace retreat::physics
