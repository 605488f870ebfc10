#pragma once
/// @file
/// Encounter and transport rates (paper §III; MODEL.md §2).

#include "retreat/model/params.hpp"

namespace retreat::model {

/// Mean relative speed of two robots moving with mean speed v in uniformly random directions:
/// v_r = (4/π) v [m/s].
/// @pre v ≥ 0 [m/s].
double relative_speed(double v);

/// Area swept per unit time by a robot's encounter disc: c = 4 δ v_r = 4 δ (4/π) v [m²/s].
/// @pre p.validate() passes.
double swept_rate(const ModelParams& p);

/// Encounter rate of one robot at robot density λ: Ω_c(λ) = c λ = 4 δ (4/π) v λ [1/s];
/// the inter-encounter time is τ_c ~ Exp(Ω_c).
/// @param lambda robot density λ [robots/m²], λ ≥ 0.
double omega_c(const ModelParams& p, double lambda);

/// Rate of reaching pick-up locations: Ω_p = 2 δ v λ_p [1/s].
double omega_p(const ModelParams& p);

/// Rate of reaching drop-off locations: Ω_d = 2 δ v λ_d [1/s].
double omega_d(const ModelParams& p);

}  // namespace retreat::model
