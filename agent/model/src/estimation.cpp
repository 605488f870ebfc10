#include "retreat/model/estimation.hpp"

#include "retreat/model/encounter.hpp"

namespace retreat::model {

// NOLINTNEXTLINE(readability-identifier-naming): L is the paper's symbol.
double mle_density(std::uint64_t onsets, double delta, double v, double L) {
  return mle_density(onsets, mle_divisor(delta, v, L));
}

// NOLINTNEXTLINE(readability-identifier-naming): L is the paper's symbol.
double mle_divisor(double delta, double v, double L) { return 4.0 * delta * relative_speed(v) * L; }

}  // namespace retreat::model
