#pragma once
/// @file
/// Cost of a swarm density and the optimal density (paper §IV-B; MODEL.md §4).

#include "retreat/model/params.hpp"

namespace retreat::model {

/// Cost of running the swarm at density λ: J(λ) = C / (T(λ) λ) + λ [robots/m²], trading the
/// swarm's size against its output. Uses the full T(λ), including ρ, so that it is the cost a
/// run is evaluated against (its minimiser does not depend on ρ; its value does).
/// @param lambda robot density λ [robots/m²], λ > 0 (J(0) = +∞).
double cost(const ModelParams& p, double lambda);

/// Density minimising J: λ* = sqrt( C (1 + λ_d/λ_p) / (2 δ v λ_d) ) [robots/m²].
/// Independent of ρ and c: interference only adds a constant to J.
/// @pre p.validate() passes.
double lambda_star(const ModelParams& p);

}  // namespace retreat::model
