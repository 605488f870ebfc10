#include "retreat/core/rng.hpp"

#include <cmath>

#include "retreat/core/seed.hpp"

namespace retreat {

Rng::Rng(std::uint64_t seed) noexcept {
  for (std::size_t k = 0; k < s_.size(); ++k) {
    s_[k] = retreat::splitmix64(seed + k * 0x9E3779B97F4A7C15ULL);
  }
  if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0) {
    s_[0] = 1;  // the all-zero state is the one fixed point of xoshiro
  }
}

double Rng::angle() noexcept {
  constexpr double pi = 3.14159265358979323846;
  return uniform(-pi, pi);
}

double Rng::exponential(double rate) noexcept {
  if (!(rate > 0.0)) {
    return HUGE_VAL;
  }
  return -std::log1p(-uniform()) / rate;
}

std::uint64_t Rng::poisson(double mean) noexcept {
  // Inversion by sequential search, in chunks of mean <= 30 so that exp(−mean) never underflows
  // (a sum of independent Poisson variables is Poisson).
  std::uint64_t total = 0;
  while (mean > 0.0) {
    const double chunk = mean > 30.0 ? 30.0 : mean;
    mean -= chunk;
    double p = std::exp(-chunk);
    double cdf = p;
    const double u = uniform();
    std::uint64_t k = 0;
    while (u > cdf && k < 1000) {
      ++k;
      p *= chunk / static_cast<double>(k);
      cdf += p;
    }
    total += k;
  }
  return total;
}

}  // namespace retreat
