#pragma once
/// @file
/// The exact solver of each robot's 2-variable barrier-certificate QP:
///
///   minimise ‖u − û‖²  subject to  a_kᵀ u ≤ b_k,  k = 1..m,
///
/// i.e. the Euclidean projection of û onto a convex polygon (possibly unbounded). Solved by the
/// incremental method of Seidel (1991) as used for 2-D velocity obstacles: constraints are added
/// one at a time; if the current optimum violates the new one, the new optimum lies on its line
/// (strict convexity), where it is the clamp of a 1-D projection to the interval the earlier
/// constraints leave. Exact up to rounding; O(m²) worst case, O(m) when few constraints bind.

#include <cstddef>
#include <vector>

#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// Half-plane aᵀu ≤ b in the space of projected-point velocities [m/s].
struct HalfPlane {
  Vec2 a = Vec2::Zero();
  double b = 0.0;
};

/// How the returned velocity was obtained.
enum class QpStatus : std::uint8_t {
  unconstrained,  ///< û itself is feasible
  optimal,        ///< exact projection onto the feasible polygon
  relaxed,        ///< the polygon was empty: every b_k < 0 was raised to 0 ("do not make any
                  ///< violated constraint worse"); u = 0 is then feasible, and the result is the
                  ///< exact projection onto that relaxed polygon
  stopped,        ///< not even the relaxed polygon admitted a solution (cannot happen with
                  ///< finite data); u = 0
};

/// Result of one QP.
struct QpResult {
  Vec2 u = Vec2::Zero();
  QpStatus status = QpStatus::unconstrained;
};

/// Projects @p u_hat onto {u : a_kᵀu ≤ b_k} for the @p count half-planes at @p constraints.
/// Constraints with a = 0 are read as 0 ≤ b.
QpResult solve_barrier_qp(const Vec2& u_hat, const HalfPlane* constraints, std::size_t count);

/// Convenience overload.
inline QpResult solve_barrier_qp(const Vec2& u_hat, const std::vector<HalfPlane>& constraints) {
  return solve_barrier_qp(u_hat, constraints.data(), constraints.size());
}

}  // namespace retreat::physics
