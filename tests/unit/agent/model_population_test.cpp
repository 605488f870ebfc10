// The population chain of retreat::model (population.hpp) against closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "retreat/model/population.hpp"

namespace retreat::model {
namespace {

TEST(PoissonWeights, SumToOneWithTheRightMean) {
  for (const double mean : {0.0, 0.5, 6.9, 40.0, 700.0}) {
    const auto w = poisson_weights(mean);
    double sum = 0.0, first = 0.0;
    for (std::size_t y = 0; y < w.size(); ++y) {
      sum += w[y];
      first += static_cast<double>(y) * w[y];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << mean;
    EXPECT_NEAR(first, mean, 1e-9 * std::max(1.0, mean)) << mean;
  }
  EXPECT_NEAR(poisson_weights(2.0)[3], std::exp(-2.0) * 8.0 / 6.0, 1e-15);
}

TEST(PopulationChain, WithoutArrivalsEveryRobotSurvivesEachStepWithOneMinusQ) {
  PopulationChain chain;
  chain.initial = 12;
  chain.dt = 0.5;
  chain.leave_per_step.assign(13, 0.01);
  const auto mean = expected_population(chain, 100.0);
  ASSERT_EQ(mean.size(), 201u);
  for (std::size_t k = 0; k < mean.size(); k += 20) {
    EXPECT_NEAR(mean[k], 12.0 * std::pow(0.99, static_cast<double>(k)), 1e-10) << k;
  }
}

TEST(PopulationChain, PoissonArrivalsAndAConstantChanceSettleAtTheGeometricStaysMean) {
  // Arrivals a·dt per step, then each robot leaves with q: the stationary mean m solves
  // m = (m + a·dt)(1 − q), m = a·dt(1 − q)/q. With the Robotarium's influx (a = λ_in|D| =
  // 0.0603 /s) and q = (λ_in/λ*)·dt, that is λ*|D|(1 − q) = 4.55: influx-matching's M/G/∞ mean.
  const double area = 3.0159, lambda_in = 0.02, lambda_star = 1.5076, dt = 0.03;
  PopulationChain chain;
  chain.dt = dt;
  chain.arrival_rate = lambda_in * area;
  const double q = lambda_in / lambda_star * dt;
  chain.leave_per_step.assign(65, q);
  const auto mean = expected_population(chain, 3000.0);  // 40 mean stays
  const double expected = chain.arrival_rate * dt * (1.0 - q) / q;
  EXPECT_NEAR(expected, lambda_star * area, 0.01);
  EXPECT_NEAR(mean.back(), expected, 1e-6 * expected);
  EXPECT_NEAR(time_mean(mean, dt, 2000.0, 3000.0), expected, 1e-6 * expected);
}

TEST(PopulationChain, ScheduledArrivalsAddOneRobotEachAndNobodyLeavesBeforeTheFirstDecision) {
  PopulationChain chain;
  chain.initial = 2;
  chain.dt = 1.0;
  chain.arrival_times = {2.5, 4.0, 4.0};
  chain.leave_per_step.assign(10, 1.0);  // everybody leaves at the first decision
  chain.first_decision = 6.0;
  const auto mean = expected_population(chain, 8.0);
  const std::vector<double> expected = {2, 2, 2, 3, 5, 5, 0, 0, 0};
  ASSERT_EQ(mean.size(), expected.size());
  for (std::size_t k = 0; k < mean.size(); ++k) EXPECT_DOUBLE_EQ(mean[k], expected[k]) << k;
}

TEST(PopulationChain, RefusesBadInputWithOneLine) {
  PopulationChain chain;
  chain.dt = 0.0;
  EXPECT_THROW(expected_population(chain, 1.0), std::invalid_argument);
  chain.dt = 0.1;
  EXPECT_THROW(expected_population(chain, -1.0), std::invalid_argument);
  chain.arrival_rate = -1.0;
  EXPECT_THROW(expected_population(chain, 1.0), std::invalid_argument);
  chain.arrival_rate = 0.0;
  chain.leave_per_step = {0.0, 1.5};
  EXPECT_THROW(expected_population(chain, 1.0), std::invalid_argument);
  EXPECT_THROW(poisson_weights(-1.0), std::invalid_argument);
}

TEST(TimeMean, AveragesTheSamplesInTheSpan) {
  const std::vector<double> series = {0, 1, 2, 3, 4};
  EXPECT_DOUBLE_EQ(time_mean(series, 0.5, 0.5, 1.5), 2.0);  // samples at 0.5, 1.0, 1.5
  EXPECT_TRUE(std::isnan(time_mean(series, 0.5, 5.0, 6.0)));
}

}  // namespace
}  // namespace retreat::model
