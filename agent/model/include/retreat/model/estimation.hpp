#pragma once
/// @file
/// Maximum-likelihood density estimate from counted encounter onsets (paper §V-B; MODEL.md §5).

#include <cstdint>

namespace retreat::model {

/// Maximum-likelihood estimate of the robot density from y_iL onsets counted in a window of
/// length L: λ̂ = y_iL / (4 δ (4/π) v L) [robots/m²]. It estimates the density of the *other*
/// robots (MODEL.md §7.1) and is implemented exactly as the paper writes it.
/// @param onsets y_iL, encounter onsets in [t − L, t] [-].
/// @param delta sensing distance δ [m], > 0.
/// @param v mean robot speed [m/s], > 0.
/// @param L window length [s], > 0.
// NOLINTNEXTLINE(readability-identifier-naming): L is the paper's symbol.
double mle_density(std::uint64_t onsets, double delta, double v, double L);

/// mle_density's divisor, 4 δ (4/π) v L [m²·s/s]: mle_density(y, δ, v, L) is y divided by it,
/// bit for bit, so that an agent deciding every step computes it once.
// NOLINTNEXTLINE(readability-identifier-naming): L is the paper's symbol.
double mle_divisor(double delta, double v, double L);

/// The same estimate with its divisor computed once: mle_density(y, δ, v, L) is
/// mle_density(y, mle_divisor(δ, v, L)).
inline double mle_density(std::uint64_t onsets, double divisor) { return static_cast<double>(onsets) / divisor; }

}  // namespace retreat::model
