#include "retreat/agent/onset_window.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "retreat/core/rng.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"

namespace retreat::agent {
namespace {

TEST(OnsetWindow, CountsAnOnsetExactlyAtTheWindowStart) {
  OnsetWindow window(90.0);
  window.add(10.0);
  EXPECT_EQ(window.count_at(100.0), 1u);  // 100 − 90 = 10 exactly
}

TEST(OnsetWindow, CountsAnOnsetExactlyAtTheQueryTime) {
  OnsetWindow window(90.0);
  window.add(100.0);
  EXPECT_EQ(window.count_at(100.0), 1u);
}

TEST(OnsetWindow, DoesNotCountAnOnsetJustBeforeTheWindowStart) {
  OnsetWindow window(90.0);
  window.add(10.0 - 1e-9);
  window.add(10.0);
  EXPECT_EQ(window.count_at(100.0), 1u);
}

TEST(OnsetWindow, DoesNotCountOnsetsAfterTheQueryTime) {
  OnsetWindow window(90.0);
  window.add(5.0);
  window.add(7.0, 3);
  EXPECT_EQ(window.count_at(6.0), 1u);
  EXPECT_EQ(window.count_at(7.0), 4u);
}

TEST(OnsetWindow, CountsSeveralOnsetsAtOneInstant) {
  OnsetWindow window(1.0);
  window.add(0.5, 2);
  window.add(0.5, 3);
  window.add(0.5, 0);
  EXPECT_EQ(window.count_at(1.0), 5u);
  EXPECT_EQ(window.entries().size(), 1u);
}

TEST(OnsetWindow, EvictsOnsetsThatLeftTheWindow) {
  OnsetWindow window(2.0);
  for (int i = 0; i < 10; ++i) {
    window.add(i);
  }
  EXPECT_EQ(window.count_at(9.0), 3u);  // 7, 8, 9
  EXPECT_EQ(window.held(), 3u);
  EXPECT_EQ(window.entries().front().time, 7.0);
}

TEST(OnsetWindow, RejectsOnsetsGoingBackInTime) {
  OnsetWindow window(2.0);
  window.add(1.0);
  EXPECT_THROW(window.add(0.5), std::invalid_argument);
  EXPECT_THROW(window.add(std::nan("")), std::invalid_argument);
}

TEST(OnsetWindow, RejectsQueriesGoingBackInTime) {
  OnsetWindow window(2.0);
  window.count_at(5.0);
  EXPECT_THROW(window.count_at(4.0), std::invalid_argument);
}

TEST(OnsetWindow, RejectsANonPositiveLength) {
  EXPECT_THROW(OnsetWindow(0.0), std::invalid_argument);
  EXPECT_THROW(OnsetWindow(-90.0), std::invalid_argument);
}

TEST(Estimator, MeanOfTheEstimateOverPoissonOnsetsIsTheTrueDensity) {
  // Onsets of a Poisson process of rate Ω_c(λ) = cλ (experiment parameters, λ = 1.5 near λ*),
  // counted in n disjoint windows [jL, (j+1)L]. Each count is Poisson(cλL) (boundary onsets
  // have probability 0), so λ̂ = y/(cL) has mean λ and variance λ/(cL) = 1.5/4.584 = 0.327.
  // The mean of n = 20000 independent λ̂ is normal to excellent accuracy (CLT; cλL·n ≈ 1.4e5
  // onsets), with standard deviation sqrt(0.327/20000) = 0.00405. A tolerance of 5 standard
  // deviations fails a correct estimator with probability 5.7e-7 (two-sided).
  const model::ModelParams p;
  const double window_length = 90.0;
  const double lambda = 1.5;
  const double c = model::swept_rate(p);
  const int windows = 20000;
  const double sigma_of_mean = std::sqrt(lambda / (c * window_length) / windows);

  retreat::Rng generator(20190520);
  const auto gap = [&] { return generator.exponential(c * lambda); };
  OnsetWindow window(window_length);
  double next_onset = gap();
  double sum = 0.0;
  for (int j = 1; j <= windows; ++j) {
    const double t = j * window_length;
    while (next_onset <= t) {
      window.add(next_onset);
      next_onset += gap();
    }
    sum += model::mle_density(window.count_at(t), p.delta, p.v, window_length);
  }
  EXPECT_NEAR(sum / windows, lambda, 5.0 * sigma_of_mean);
}

}  // namespace
}  // namespace retreat::agent
