#include <gtest/gtest.h>

#include <cmath>

#include "retreat/model/control.hpp"

namespace retreat::model {
namespace {

struct Gains {
  double lambda_star;
  double lambda_in;
  double K_p;
};

// The experiment's gains, then others, including λ_in = 0 and K_p = 0.
const Gains gain_sets[] = {
    {1.5076, 0.02, 0.03}, {0.5, 0.1, 1.0}, {3.0, 0.0, 0.2}, {2.0, 0.05, 0.0}};

TEST(Epsilon, IsZeroAtLambdaStar) {
  for (const Gains& g : gain_sets) {
    EXPECT_EQ(epsilon(g.lambda_star, g.lambda_star, g.lambda_in, g.K_p), 0.0);
  }
}

TEST(Epsilon, IsZeroBelowLambdaStar) {
  for (const Gains& g : gain_sets) {
    for (const double fraction : {0.0, 0.1, 0.5, 0.999999}) {
      EXPECT_EQ(epsilon(fraction * g.lambda_star, g.lambda_star, g.lambda_in, g.K_p), 0.0);
    }
  }
}

TEST(Epsilon, IsZeroForANanDensity) { EXPECT_EQ(epsilon(std::nan(""), 1.5, 0.02, 0.03), 0.0); }

TEST(Epsilon, AboveLambdaStarMakesTheEnsembleDynamicsProportional) {
  // dλ/dt = λ_in − ε(λ)λ must equal K_p (λ* − λ).
  for (const Gains& g : gain_sets) {
    for (const double factor : {1.000001, 1.01, 1.5, 2.0, 10.0}) {
      const double lambda = factor * g.lambda_star;
      const double rate = epsilon(lambda, g.lambda_star, g.lambda_in, g.K_p);
      EXPECT_NEAR(g.lambda_in - rate * lambda, g.K_p * (g.lambda_star - lambda), 1e-12);
      EXPECT_GE(rate, 0.0);
    }
  }
}

}  // namespace
}  // namespace retreat::model
