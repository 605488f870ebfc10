// The project's one portable generator (retreat/core/rng.hpp): its values are pinned, so that
// a change of compiler, standard library or platform that altered a single draw fails here
// before it alters a trajectory. The expected values were computed by an independent
// implementation of the published algorithms (a few lines of Python, in the comments).

#include "retreat/core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>

#include "retreat/core/seed.hpp"

namespace {

// SplitMix64's reference sequence from state 0 (Steele, Lea, Flood 2014; the first value is the
// one every SplitMix64 implementation is checked against).
TEST(SplitMix64, MatchesTheReferenceSequenceFromStateZero) {
  EXPECT_EQ(retreat::splitmix64(0), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(retreat::splitmix64(0x9E3779B97F4A7C15ULL), 0x6e789e6aa1b965f4ULL);
  EXPECT_EQ(retreat::splitmix64(2 * 0x9E3779B97F4A7C15ULL), 0x06c45d188009454fULL);
}

// xoshiro256** seeded by SplitMix64 expansion (Rng's constructor), checked against
// Blackman and Vigna's algorithm written independently:
//   s = [splitmix(seed + k*γ) for k in 0..3]; r = rotl(s1*5, 7)*9; ...
TEST(Rng, GivesThePinnedStreamForAPinnedSeed) {
  retreat::Rng rng(20190520);
  EXPECT_EQ(rng(), 0x85582ad2757f318aULL);
  EXPECT_EQ(rng(), 0x5248f66046e548cbULL);
  EXPECT_EQ(rng(), 0xd5868bfa07c872b7ULL);
}

TEST(Rng, UniformTakesTheTop53BitsOfTheNextDraw) {
  retreat::Rng a(20190520);
  retreat::Rng b(20190520);
  EXPECT_EQ(a.uniform(), static_cast<double>(b() >> 11) * 0x1.0p-53);
}

// counter_uniform(key, k) is SplitMix64's k-th value from `key`, as a 53-bit fraction.
TEST(CounterUniform, IsTheKthSplitMix64ValueAsAFractionOfOne) {
  EXPECT_EQ(retreat::counter_uniform(7, 0),
            static_cast<double>(0x63cbe1e459320dd7ULL >> 11) * 0x1.0p-53);
  EXPECT_EQ(retreat::counter_uniform(7, 1),
            static_cast<double>(0x044c3cd7f43c661cULL >> 11) * 0x1.0p-53);
  EXPECT_EQ(retreat::counter_uniform(7, 2),
            static_cast<double>(0xe6984080bab12a02ULL >> 11) * 0x1.0p-53);
  EXPECT_DOUBLE_EQ(retreat::counter_uniform(7, 0), 0.3898297483912715);
}

TEST(CounterUniform, DependsOnTheKeyAndTheCounterOnlyAndStaysBelowOne) {
  std::set<double> seen;
  for (std::uint64_t k = 0; k < 1000; ++k) {
    const double u = retreat::counter_uniform(42, k);
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
    EXPECT_EQ(u, retreat::counter_uniform(42, k));  // the same whatever was drawn before
    seen.insert(u);
  }
  EXPECT_EQ(seen.size(), 1000u);
  EXPECT_NE(retreat::counter_uniform(42, 5), retreat::counter_uniform(43, 5));
}


// Rng::poisson as it was written before PoissonDraw, a chunk of mean <= 30 at a time with its
// own exp(−chunk) (the robot-by-robot chain's predictions were computed with it).
std::uint64_t poisson_written_out(retreat::Rng& rng, double mean) {
  std::uint64_t total = 0;
  while (mean > 0.0) {
    const double chunk = mean > 30.0 ? 30.0 : mean;
    mean -= chunk;
    double p = std::exp(-chunk);
    double cdf = p;
    const double u = rng.uniform();
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

TEST(PoissonDraw, DrawsWhatPoissonByInversionDrawsChunkByChunk) {
  for (const double mean : {0.0, -1.0, 1e-3, 0.5, 3.7, 29.999, 30.0, 30.5, 60.0, 75.0}) {
    retreat::Rng expected(42);
    retreat::Rng by_rng(42);
    retreat::Rng by_draw(42);
    const retreat::PoissonDraw draw(mean);
    for (int k = 0; k < 2000; ++k) {
      const std::uint64_t want = poisson_written_out(expected, mean);
      ASSERT_EQ(by_rng.poisson(mean), want) << "mean " << mean << ", draw " << k;
      ASSERT_EQ(draw(by_draw), want) << "mean " << mean << ", draw " << k;
    }
    EXPECT_EQ(by_draw(), expected()) << "mean " << mean << ": as many uniforms taken";
  }
}

}  // namespace
