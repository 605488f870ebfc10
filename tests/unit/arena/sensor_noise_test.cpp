// A robot's imperfect sensor (physics::SensorNoise): missed and false onsets, seeded per robot
// and counter-based per tick.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "retreat/core/seed.hpp"
#include "retreat/physics/sensor_noise.hpp"

namespace retreat::physics {
namespace {

const std::uint64_t key = seed_for(2026, 3, Stream::sensor);

TEST(PhysicsSensorNoise, APerfectSensorReportsEveryOnsetAndNothingElse) {
  const SensorNoise perfect;
  ASSERT_TRUE(perfect.perfect());
  for (const std::uint32_t n : {0U, 1U, 2U, 7U}) {
    for (std::int64_t tick = 0; tick < 100; ++tick) EXPECT_EQ(perfect.sense(n, key, tick), n);
  }
}

TEST(PhysicsSensorNoise, TheSameTickGivesTheSameCountAndAnotherRobotOtherNoise) {
  const SensorNoise noisy{0.5, 5.0, 0.03};
  std::uint32_t differ = 0;
  for (std::int64_t tick = 0; tick < 2000; ++tick) {
    const auto once = noisy.sense(3, key, tick);
    EXPECT_EQ(noisy.sense(3, key, tick), once) << tick;  // a resent frame says the same
    differ += noisy.sense(3, seed_for(2026, 4, Stream::sensor), tick) != once ? 1U : 0U;
  }
  EXPECT_GT(differ, 500U);  // robot 4's sensor is not robot 3's
}

TEST(PhysicsSensorNoise, KeepsEachOnsetWithOneMinusTheMissChance) {
  // One true onset per tick over n = 200,000 ticks, missed = 0.3: the kept count is
  // Binomial(n, 0.7), standard deviation sqrt(n·0.21) = 205; 5 standard deviations (1,025)
  // fail a correct sensor with probability 5.7e-7.
  const SensorNoise noisy{0.3, 0.0, 0.03};
  const int n = 200000;
  double kept = 0.0;
  for (std::int64_t tick = 0; tick < n; ++tick) kept += noisy.sense(1, key, tick);
  EXPECT_NEAR(kept, 0.7 * n, 5.0 * std::sqrt(n * 0.21));
  EXPECT_EQ(SensorNoise({1.0, 0.0, 0.03}).sense(4, key, 17), 0U);  // misses everything
}

TEST(PhysicsSensorNoise, AddsFalseOnsetsAtTheirRate) {
  // No true onsets, 0.5 false onsets per second, dt = 0.03 s, n = 200,000 ticks (6,000 s): the
  // total is Poisson with mean 3,000, standard deviation 54.8; 5 of them (274) as above.
  const SensorNoise noisy{0.0, 0.5, 0.03};
  const int n = 200000;
  double reported = 0.0;
  for (std::int64_t tick = 0; tick < n; ++tick) reported += noisy.sense(0, key, tick);
  const double mean = 0.5 * 0.03 * n;
  EXPECT_NEAR(reported, mean, 5.0 * std::sqrt(mean));
}

}  // namespace
}  // namespace retreat::physics
