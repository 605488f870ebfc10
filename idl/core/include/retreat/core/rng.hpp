#pragma once
/// @file
/// The generators every seeded draw of retreat comes from: the physics, the influx and the
/// agents' coins.
///
/// Why not std::mt19937_64 and the std distributions: a world holds one generator per robot and
/// must scale to 10^5 robots (mt19937_64 keeps 2.5 KiB of state, xoshiro256** 32 bytes), and
/// the std distributions are implementation-defined, so the same seed would give different runs
/// with libstdc++ and libc++. Every sampler below is written out, hence bit-for-bit portable
/// (tests/unit/core/rng_test.cpp pins their values; the test command checks that a Clang and
/// libc++ build gives the same golden trajectories as the GCC and libstdc++ one).

#include <array>
#include <cstdint>

#include "retreat/core/seed.hpp"

namespace retreat {

/// xoshiro256** (Blackman, Vigna 2018), seeded by expanding one 64-bit seed with SplitMix64.
/// Meets the UniformRandomBitGenerator requirements. Seeds come from
/// retreat::seed_for(scenario_seed, robot_id, stream), never from a clock.
class Rng {
 public:
  using result_type = std::uint64_t;

  /// A generator whose whole state is derived from @p seed.
  explicit Rng(std::uint64_t seed = 0) noexcept;

  static constexpr result_type min() noexcept { return 0; }
  static constexpr result_type max() noexcept { return ~result_type{0}; }

  /// Next 64 random bits.
  result_type operator()() noexcept {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform on [0, 1), 53 random bits.
  double uniform() noexcept { return static_cast<double>((*this)() >> 11) * 0x1.0p-53; }

  /// Uniform on [@p lo, @p hi).
  double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }

  /// Uniform angle on [-π, π) [rad].
  double angle() noexcept;

  /// Exp(@p rate): mean 1/rate [s if rate is 1/s]; +infinity when rate <= 0.
  double exponential(double rate) noexcept;

  /// Poisson(@p mean) by inversion (exact; cost grows linearly with the mean); 0 if mean <= 0.
  /// PoissonDraw draws the same numbers with exp(−mean) computed once, for many draws.
  std::uint64_t poisson(double mean) noexcept;

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) noexcept {
    return (x << k) | (x >> (64 - k));
  }
  std::array<std::uint64_t, 4> s_{};
};

/// Draws of Poisson(@p mean) for one mean: the numbers Rng::poisson(mean) draws from the same
/// generator, bit for bit, without its exp(−mean) per draw (the robot-by-robot chain draws one
/// per robot and step, all with that step's mean).
class PoissonDraw {
 public:
  /// Splits @p mean into the chunks of at most 30 that Rng::poisson draws one after another.
  explicit PoissonDraw(double mean) noexcept;

  /// One draw, from @p rng.
  std::uint64_t operator()(Rng& rng) const noexcept;

 private:
  std::uint64_t full_chunks_ = 0;  ///< chunks of mean 30, drawn first
  double last_ = 0.0;              ///< the last chunk's mean, in (0, 30]; 0: none
  double exp_last_ = 1.0;          ///< exp(−last_)
};

/// The @p counter-th value of the SplitMix64 sequence that starts at @p key, uniform on [0, 1)
/// with 53 random bits: a counter-based draw, so that draw k does not depend on how many draws
/// came before it (an agent's coin for step k is the same whether or not it looked ahead).
/// SplitMix64 (Steele, Lea, Flood 2014) outputs mix(key + (i + 1)·γ) for i = 0, 1, ...
constexpr double counter_uniform(std::uint64_t key, std::uint64_t counter) noexcept {
  // splitmix64() adds γ itself: its argument is the state before the step.
  return static_cast<double>(splitmix64(key + counter * 0x9E3779B97F4A7C15ULL) >> 11) * 0x1.0p-53;
}

}  // namespace retreat
