#include "retreat/physics/sensor_noise.hpp"

#include <cmath>

#include "retreat/core/rng.hpp"

namespace retreat::physics {

std::uint32_t SensorNoise::sense(std::uint32_t true_onsets, std::uint64_t key, std::int64_t tick) const {
  if (perfect()) return true_onsets;
  const std::uint64_t base = static_cast<std::uint64_t>(tick) * 256U;
  std::uint32_t sensed = 0;
  for (std::uint32_t j = 0; j < true_onsets; ++j) {
    if (j >= 255U || retreat::counter_uniform(key, base + j) >= missed) ++sensed;
  }
  const double mean = false_rate * dt;
  if (mean > 0.0) {
    // Inversion: the smallest k whose Poisson CDF reaches u.
    const double u = retreat::counter_uniform(key, base + 255U);
    double p = std::exp(-mean);
    double cdf = p;
    std::uint32_t k = 0;
    while (u > cdf && k < 1000U) {
      ++k;
      p *= mean / static_cast<double>(k);
      cdf += p;
    }
    sensed += k;
  }
  return sensed;
}

}  // namespace retreat::physics
