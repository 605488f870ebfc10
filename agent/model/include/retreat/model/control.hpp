#pragma once
/// @file
/// The paper's one-sided density controller (paper §V-A; MODEL.md §5).

namespace retreat::model {

/// Per-robot retreat rate of the one-sided proportional controller [1/s]:
///
///     ε(λ) = (λ_in − K_p (λ* − λ)) / λ    if λ > λ*
///     ε(λ) = 0                            otherwise
///
/// so that dλ/dt = λ_in − ε(λ) λ = K_p (λ* − λ) above λ*.
/// @param lambda density λ (true or estimated) [robots/m²].
/// @param lambda_star optimal density λ* [robots/m²], λ* ≥ 0.
/// @param lambda_in influx λ_in [robots/(m²·s)].
/// @param K_p proportional gain K_p [1/s].
// NOLINTNEXTLINE(readability-identifier-naming): K_p is the paper's symbol.
double epsilon(double lambda, double lambda_star, double lambda_in, double K_p);

}  // namespace retreat::model
