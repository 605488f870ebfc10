#include <gtest/gtest.h>

#include <cmath>

#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"

namespace retreat::model {
namespace {

const double pi = std::acos(-1.0);

TEST(Encounter, RelativeSpeedIsFourOverPiTimesTheSpeed) {
  EXPECT_DOUBLE_EQ(relative_speed(1.0), 4.0 / pi);
  EXPECT_DOUBLE_EQ(relative_speed(0.1), 0.4 / pi);
}

TEST(Encounter, RatesFollowTheSweptAreaModel) {
  ModelParams p;
  p.delta = 0.11;
  p.v = 1.0;
  p.lambda_p = 0.82;
  p.lambda_d = 0.66;
  const double c = 4.0 * 0.11 * (4.0 / pi) * 1.0;
  EXPECT_DOUBLE_EQ(swept_rate(p), c);
  EXPECT_DOUBLE_EQ(omega_c(p, 0.99), c * 0.99);
  EXPECT_DOUBLE_EQ(omega_p(p), 2.0 * 0.11 * 1.0 * 0.82);
  EXPECT_DOUBLE_EQ(omega_d(p), 2.0 * 0.11 * 1.0 * 0.66);
}

TEST(Estimation, MleDensityIsOnsetsOverSweptAreaOfTheWindow) {
  // Experiment parameters: 7 onsets in L = 90 s.
  const double expected = 7.0 / (4.0 * 0.1 * (4.0 / pi) * 0.1 * 90.0);
  EXPECT_NEAR(mle_density(7, 0.1, 0.1, 90.0), expected, 1e-15 * expected);
  EXPECT_EQ(mle_density(0, 0.1, 0.1, 90.0), 0.0);
}

TEST(Estimation, MleDensityInvertsTheExpectedOnsetCount) {
  // E[y] = Ω_c(λ) L, so λ̂(E[y]) = λ when y is taken as real-valued; with an integer y that
  // equals Ω_c L exactly the estimate must return λ.
  ModelParams p;
  const double window = 1.0 / (swept_rate(p) * 2.0);  // makes Ω_c(2) L = 1 onset
  EXPECT_NEAR(mle_density(1, p.delta, p.v, window), 2.0, 1e-12);
}

}  // namespace
}  // namespace retreat::model
