#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "retreat/model/optimum.hpp"

namespace retreat::model {
namespace {

/// Minimiser of a unimodal f on [a, b] by golden-section search, to an interval of 1e-10.
double golden_section_minimum(const std::function<double(double)>& f, double a, double b) {
  const double inv_phi = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = b - inv_phi * (b - a);
  double x2 = a + inv_phi * (b - a);
  double f1 = f(x1);
  double f2 = f(x2);
  while (b - a > 1e-10) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - inv_phi * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + inv_phi * (b - a);
      f2 = f(x2);
    }
  }
  return 0.5 * (a + b);
}

/// The paper's three parameter sets (MODEL.md §6, each with C = 0.03 unless it has none) and
/// two asymmetric ones.
std::vector<ModelParams> parameter_sets() {
  ModelParams experiment;  // defaults
  ModelParams throughput_curve;
  throughput_curve.v = 0.1;
  throughput_curve.delta = 0.11;
  throughput_curve.lambda_p = 0.82;
  throughput_curve.lambda_d = 0.66;
  ModelParams validation;
  validation.delta = 0.11;
  validation.v = 1.0;
  validation.C = 0.5;
  ModelParams few_pickups;
  few_pickups.lambda_p = 0.3;
  few_pickups.lambda_d = 5.0;
  few_pickups.C = 0.1;
  few_pickups.delta = 0.05;
  few_pickups.v = 0.5;
  few_pickups.rho = 0.5;
  ModelParams few_dropoffs = few_pickups;
  few_dropoffs.lambda_p = 5.0;
  few_dropoffs.lambda_d = 0.3;
  few_dropoffs.rho = 20.0;
  return {experiment, throughput_curve, validation, few_pickups, few_dropoffs};
}

TEST(Optimum, LambdaStarOfTheRobotariumExperimentIs1Point5076) {
  EXPECT_NEAR(lambda_star(ModelParams{}), 1.5076, 1e-4);
}

TEST(Optimum, OptimalPopulationOfTheRobotariumEllipseIs4Point55Robots) {
  const double area = std::acos(-1.0) * 1.2 * 0.8;  // |D| [m²]
  EXPECT_NEAR(lambda_star(ModelParams{}) * area, 4.55, 0.01);
}

TEST(Optimum, CostIsMinimalAtLambdaStarByGoldenSectionSearch) {
  for (const ModelParams& p : parameter_sets()) {
    const double found =
        golden_section_minimum([&](double lambda) { return cost(p, lambda); }, 1e-3, 50.0);
    EXPECT_NEAR(found, lambda_star(p), 1e-4) << "C=" << p.C << " lambda_p=" << p.lambda_p;
  }
}

TEST(Optimum, CostAtLambdaStarIsBelowEveryPointOfADenseGrid) {
  for (const ModelParams& p : parameter_sets()) {
    const double best = cost(p, lambda_star(p));
    for (int i = 1; i <= 10000; ++i) {
      const double lambda = lambda_star(p) * 0.001 * i;  // 0.001 λ* .. 10 λ*
      EXPECT_LE(best, cost(p, lambda) + 1e-12) << "lambda=" << lambda;
    }
  }
}

TEST(Optimum, LambdaStarDoesNotDependOnRho) {
  for (ModelParams p : parameter_sets()) {
    const double reference = lambda_star(p);
    for (const double rho : {0.1, 2.44, 100.0}) {
      p.rho = rho;
      EXPECT_EQ(lambda_star(p), reference);
      const double found =
          golden_section_minimum([&](double lambda) { return cost(p, lambda); }, 1e-3, 50.0);
      EXPECT_NEAR(found, reference, 1e-4) << "rho=" << rho;
    }
  }
}

TEST(Optimum, CostStillDependsOnRho) {
  // The minimiser ignores ρ, the value does not: J is what a run is evaluated against.
  ModelParams slow;
  slow.rho = 0.5;
  ModelParams fast;
  fast.rho = 20.0;
  EXPECT_GT(cost(slow, 1.5), cost(fast, 1.5));
}

}  // namespace
}  // namespace retreat::model
