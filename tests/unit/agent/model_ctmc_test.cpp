#include <gtest/gtest.h>

#include <vector>

#include "retreat/model/ctmc.hpp"
#include "retreat/model/encounter.hpp"

namespace retreat::model {
namespace {

/// A grid spanning the paper's three parameter sets and beyond.
std::vector<ModelParams> parameter_grid() {
  std::vector<ModelParams> grid;
  for (const double lambda_p : {0.3, 0.82, 1.32, 5.0}) {
    for (const double lambda_d : {0.3, 0.66, 1.32, 5.0}) {
      for (const double delta : {0.05, 0.11}) {
        for (const double v : {0.1, 1.0}) {
          for (const double rho : {0.5, 2.44, 20.0}) {
            ModelParams p;
            p.lambda_p = lambda_p;
            p.lambda_d = lambda_d;
            p.delta = delta;
            p.v = v;
            p.rho = rho;
            grid.push_back(p);
          }
        }
      }
    }
  }
  return grid;
}

const double densities[] = {0.0, 0.01, 0.5, 0.99, 1.5076, 4.0, 10.0, 50.0};

TEST(Ctmc, GeneratorRowsSumToZero) {
  for (const ModelParams& p : parameter_grid()) {
    for (const double lambda : densities) {
      const Eigen::Matrix4d g = generator(p, lambda);
      for (Eigen::Index row = 0; row < 4; ++row) {
        EXPECT_NEAR(g.row(row).sum(), 0.0, 1e-12);
      }
    }
  }
}

TEST(Ctmc, GeneratorHasThePapersTransitions) {
  ModelParams p;
  const double lambda = 0.99;
  const double c_lambda = swept_rate(p) * lambda;
  const Eigen::Matrix4d g = generator(p, lambda);
  using S = CtmcState;
  EXPECT_DOUBLE_EQ(g(S::f, S::l), omega_p(p));
  EXPECT_DOUBLE_EQ(g(S::f, S::fc), c_lambda);
  EXPECT_DOUBLE_EQ(g(S::l, S::f), omega_d(p));
  EXPECT_DOUBLE_EQ(g(S::l, S::lc), c_lambda);
  EXPECT_DOUBLE_EQ(g(S::fc, S::f), p.rho);
  EXPECT_DOUBLE_EQ(g(S::lc, S::l), p.rho);
  EXPECT_EQ(g(S::f, S::lc), 0.0);
  EXPECT_EQ(g(S::fc, S::lc), 0.0);
}

TEST(Ctmc, NumericStationaryDistributionEqualsTheClosedForm) {
  for (const ModelParams& p : parameter_grid()) {
    for (const double lambda : densities) {
      const Eigen::Vector4d closed = stationary_closed_form(p, lambda);
      const Eigen::Vector4d numeric = stationary_numeric(p, lambda);
      EXPECT_LE((closed - numeric).cwiseAbs().maxCoeff(), 1e-12)
          << "lambda_p=" << p.lambda_p << " lambda_d=" << p.lambda_d << " delta=" << p.delta
          << " v=" << p.v << " rho=" << p.rho << " lambda=" << lambda;
    }
  }
}

TEST(Ctmc, ClosedFormIsAProbabilityVectorInBalance) {
  for (const ModelParams& p : parameter_grid()) {
    for (const double lambda : densities) {
      const Eigen::Vector4d pi = stationary_closed_form(p, lambda);
      EXPECT_NEAR(pi.sum(), 1.0, 1e-14);
      EXPECT_GE(pi.minCoeff(), 0.0);
      EXPECT_LE((pi.transpose() * generator(p, lambda)).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(Ctmc, ThroughputIsTheDropOffRateTimesTheLoadedProbability) {
  for (const ModelParams& p : parameter_grid()) {
    for (const double lambda : densities) {
      const double from_chain = omega_d(p) * stationary_numeric(p, lambda)(CtmcState::l);
      EXPECT_NEAR(throughput(p, lambda), from_chain, 1e-12);
      EXPECT_DOUBLE_EQ(output(p, lambda), throughput(p, lambda) * lambda);
    }
  }
}

TEST(Ctmc, OutputGrowsSubLinearlyWithDensity) {
  // The throughput-curve set of the paper (MODEL.md §6): T(λ)λ increases, T(λ) decreases.
  ModelParams p;
  p.v = 0.1;
  p.delta = 0.11;
  p.lambda_p = 0.82;
  p.lambda_d = 0.66;
  for (double lambda = 0.1; lambda < 20.0; lambda += 0.1) {
    EXPECT_GT(output(p, lambda + 0.1), output(p, lambda));
    EXPECT_LT(throughput(p, lambda + 0.1), throughput(p, lambda));
  }
}

}  // namespace
}  // namespace retreat::model
