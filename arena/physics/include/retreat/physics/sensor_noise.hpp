#pragma once
/// @file
/// A robot's imperfect proximity sensor: missed encounter onsets and false ones (issue 14).

#include <cstdint>

namespace retreat::physics {

/// What one robot's sensor reports in one tick, given the world's true onsets.
struct SensorNoise {
  double missed = 0.0;      ///< chance of missing each true onset [-], in [0, 1]
  double false_rate = 0.0;  ///< rate of spurious onsets [1/s], >= 0
  double dt = 0.03;         ///< the tick [s]

  /// Whether the sensor is perfect (then sense() returns its input and draws nothing).
  bool perfect() const noexcept { return missed == 0.0 && false_rate == 0.0; }

  /// The onsets reported at @p tick: each of @p true_onsets kept with chance 1 − missed, plus a
  /// Poisson number with mean false_rate·dt. The draws are counter-based on @p key (pass
  /// `seed_for(scenario seed, robot id, Stream::sensor)`) and the tick: draw j of tick k is
  /// counter_uniform(key, 256·k + j), j < 255 for the true onsets (an onset past the 255th of one
  /// tick is kept) and j = 255 for the false ones. So the same tick always gives the same count,
  /// however often its frame is sent, and the noise does not depend on anything else.
  std::uint32_t sense(std::uint32_t true_onsets, std::uint64_t key, std::int64_t tick) const;
};

}  // namespace retreat::physics
