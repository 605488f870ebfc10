#pragma once
/// @file
/// Arrival times of waiting robots: λ_in·|D| robots per second, steady or Poisson.

#include <cstdint>

#include "retreat/physics/params.hpp"
#include "retreat/core/rng.hpp"

namespace retreat::physics {

/// The arrival process. Arrivals say when the next waiting robot may enter; whether one is
/// waiting, and whether there is room, is the world's business.
class Influx {
 public:
  /// Steady: arrivals at k/rate, k = 1, 2, ...; Poisson: Exp(rate) gaps from @p world_rng.
  /// @p arrivals_per_second = λ_in·|D| [1/s]; 0 means no arrivals.
  Influx(InfluxKind kind, double arrivals_per_second, Rng& world_rng);

  /// Number of arrivals in (previous call's time, @p time] [s].
  std::uint32_t arrivals_until(double time, Rng& world_rng);

  /// Time of the next arrival [s] (+infinity if none).
  double next_arrival() const noexcept { return next_; }

 private:
  InfluxKind kind_;
  double rate_;
  std::uint64_t count_ = 0;  // arrivals so far (steady: next_ = (count_+1)/rate_, no drift)
  double next_;
};

}  // namespace retreat::physics
