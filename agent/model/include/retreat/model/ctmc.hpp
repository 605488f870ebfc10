#pragma once
/// @file
/// The four-state CTMC of one robot (paper §IV; MODEL.md §3) and the throughput it implies.

#include <Eigen/Core>

#include "retreat/model/params.hpp"

namespace retreat::model {

/// Indices of the CTMC's states in generator rows/columns and in stationary vectors.
struct CtmcState {
  static constexpr Eigen::Index f = 0;   ///< free (searching for a pick-up location)
  static constexpr Eigen::Index l = 1;   ///< loaded (searching for a drop-off location)
  static constexpr Eigen::Index fc = 2;  ///< free and resolving an encounter
  static constexpr Eigen::Index lc = 3;  ///< loaded and resolving an encounter
};

/// Generator G of the CTMC over {f, l, fc, lc} (rows = from, columns = to) [1/s]:
///
///     f  [ -(cλ + mλ_p)   mλ_p          cλ   0  ]
///     l  [  mλ_d         -(cλ + mλ_d)   0    cλ ]
///     fc [  ρ             0            -ρ    0  ]
///     lc [  0             ρ             0   -ρ  ]
///
/// with c = 4δ(4/π)v and m = 2δv. Every row sums to 0.
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
/// @pre p.validate() passes.
Eigen::Matrix4d generator(const ModelParams& p, double lambda);

/// Stationary distribution π (πᵀG = 0, Σπ = 1) in closed form, order {f, l, fc, lc} [-]:
/// π_f = 1 / ((1 + λ_p/λ_d)(1 + cλ/ρ)), π_l = (λ_p/λ_d) π_f, π_fc = (cλ/ρ) π_f,
/// π_lc = (cλ/ρ) π_l.
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
Eigen::Vector4d stationary_closed_form(const ModelParams& p, double lambda);

/// Stationary distribution π computed numerically from generator(): solves Gᵀπ = 0 with one
/// balance equation replaced by Σπ = 1, by full-pivot LU. A cross-check of the closed form.
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
Eigen::Vector4d stationary_numeric(const ModelParams& p, double lambda);

/// Deliveries per robot per unit time:
/// T(λ) = m λ_d π_l = 2δv · (λ_p λ_d / (λ_p + λ_d)) / (1 + cλ/ρ) [1/s].
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
double throughput(const ModelParams& p, double lambda);

/// Swarm output: deliveries per unit area per unit time, T(λ) λ [1/(m²·s)].
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
double output(const ModelParams& p, double lambda);

}  // namespace retreat::model
