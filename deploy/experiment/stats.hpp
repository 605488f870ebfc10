#pragma once
/// @file
/// The few statistics the experiments report: moments, quantiles, histograms, and the
/// Kolmogorov–Smirnov distance to an exponential distribution.

#include <cstddef>
#include <vector>

namespace retreat::experiment {

/// Mean, sample standard deviation (n − 1), standard error of the mean, min and max.
struct Moments {
  std::size_t n = 0;
  double mean = 0.0;
  double sd = 0.0;  ///< 0 for fewer than 2 values
  double se = 0.0;  ///< sd / √n
  double min = 0.0;
  double max = 0.0;
};
Moments moments(const std::vector<double>& values);

/// Linear-interpolation quantile (q in [0, 1]) of `values`; NaN when empty.
double quantile(std::vector<double> values, double q);

/// A histogram normalised to a density: bins of equal width from 0 to `upper`.
struct Histogram {
  double width = 0.0;            ///< bin width
  std::vector<double> centres;   ///< bin centres
  std::vector<double> density;   ///< count / (n · width): comparable with a probability density
  std::size_t outside = 0;       ///< values ≥ upper (counted in n, drawn in no bin)
};
Histogram histogram(const std::vector<double>& values, double upper, int bins);

/// sup_x |F_n(x) − (1 − e^(−rate·x))|, the one-sample Kolmogorov–Smirnov statistic of `values`
/// against Exp(rate).
double ks_exponential(std::vector<double> values, double rate);

}  // namespace retreat::experiment
