#include "retreat/physics/barrier_qp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace retreat::physics {
namespace {

/// Slack for "satisfied": rounding in aᵀu is about ε·‖a‖·‖u‖, so a point exactly on a line may
/// read as violating it by a few ulps.
double slack(const Vec2& a, const Vec2& u, double b) {
  return 1e-12 * (a.norm() * (u.norm() + 1e-3) + std::abs(b));
}

/// aᵀu ≤ b + slack(a, u, b). The slack (two square roots) is needed only when aᵀu > b: b plus
/// a slack ≥ 0 rounds to at least b, so aᵀu ≤ b already decides, with the same answer (for
/// numbers; a NaN never reaches here from a world whose poses are finite).
bool satisfied(const Vec2& a, const Vec2& u, double b) {
  const double au = a.dot(u);
  return au <= b || au <= b + slack(a, u, b);
}

double bound_of(const HalfPlane& c, bool relax) { return relax ? std::max(c.b, 0.0) : c.b; }

/// The incremental solve (Seidel 1991). Invariant: u is the projection of û onto the polygon of
/// the constraints seen so far. If constraint k holds at u, u stays optimal. Otherwise the new
/// optimum lies on line k: if it were strictly inside half-plane k, it would be a local, hence
/// global, optimum of the earlier problem, i.e. u, which violates k. On the line
/// p0 + t·d, the earlier constraints leave an interval [lo, hi] of t, and the projection of û
/// onto the line clamped to that interval is the optimum (a 1-D strictly convex problem).
/// Returns false if the polygon is empty.
bool solve(const Vec2& u_hat, const HalfPlane* c, std::size_t n, bool relax, Vec2& u) {
  u = u_hat;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2& a = c[k].a;
    const double b = bound_of(c[k], relax);
    const double aa = a.squaredNorm();
    if (aa == 0.0) {
      if (b < 0.0) {
        return false;
      }
      continue;
    }
    if (satisfied(a, u, b)) {
      continue;
    }
    const double norm = std::sqrt(aa);
    const Vec2 p0 = a * (b / aa);
    const Vec2 d(-a.y() / norm, a.x() / norm);
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < k; ++j) {
      const Vec2& aj = c[j].a;
      const double bj = bound_of(c[j], relax);
      const double numerator = bj - aj.dot(p0);
      const double denominator = aj.dot(d);
      if (std::abs(denominator) <= 1e-12 * aj.norm()) {
        // Parallel lines: all of line k is on one side of constraint j.
        if (numerator < -slack(aj, p0, bj)) {
          return false;
        }
        continue;
      }
      const double t = numerator / denominator;
      if (denominator > 0.0) {
        hi = std::min(hi, t);
      } else {
        lo = std::max(lo, t);
      }
    }
    if (lo > hi) {
      // Empty unless the interval is empty by rounding only (lines through one vertex).
      if (lo - hi > 1e-9 * (1.0 + std::abs(lo) + std::abs(hi))) {
        return false;
      }
      const double mid = 0.5 * (lo + hi);
      lo = mid;
      hi = mid;
    }
    const double t = std::clamp(d.dot(u_hat - p0), lo, hi);
    u = p0 + t * d;
  }
  return true;
}

}  // namespace

QpResult solve_barrier_qp(const Vec2& u_hat, const HalfPlane* constraints, std::size_t count) {
  QpResult result;
  bool feasible_hat = true;
  for (std::size_t k = 0; k < count && feasible_hat; ++k) {
    const HalfPlane& c = constraints[k];
    feasible_hat = satisfied(c.a, u_hat, c.b);
  }
  if (feasible_hat) {
    result.u = u_hat;
    result.status = QpStatus::unconstrained;
    return result;
  }
  if (solve(u_hat, constraints, count, false, result.u)) {
    result.status = QpStatus::optimal;
    return result;
  }
  if (solve(u_hat, constraints, count, true, result.u)) {
    result.status = QpStatus::relaxed;
    return result;
  }
  result.u = Vec2::Zero();
  result.status = QpStatus::stopped;
  return result;
}

}  // namespace retreat::physics
