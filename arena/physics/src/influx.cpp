#include "retreat/physics/influx.hpp"

#include <cmath>

namespace retreat::physics {

Influx::Influx(InfluxKind kind, double arrivals_per_second, Rng& world_rng)
    : kind_(kind), rate_(arrivals_per_second), next_(HUGE_VAL) {
  if (rate_ > 0.0) {
    next_ = kind_ == InfluxKind::steady ? 1.0 / rate_ : world_rng.exponential(rate_);
  }
}

std::uint32_t Influx::arrivals_until(double time, Rng& world_rng) {
  std::uint32_t arrivals = 0;
  while (next_ <= time) {
    ++arrivals;
    ++count_;
    next_ = kind_ == InfluxKind::steady ? static_cast<double>(count_ + 1) / rate_
                                        : next_ + world_rng.exponential(rate_);
  }
  return arrivals;
}

}  // namespace retreat::physics
