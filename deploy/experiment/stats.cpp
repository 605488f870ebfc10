#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace retreat::experiment {

Moments moments(const std::vector<double>& values) {
  Moments m;
  m.n = values.size();
  if (values.empty()) return m;
  double sum = 0.0;
  m.min = values.front();
  m.max = values.front();
  for (const double v : values) {
    sum += v;
    m.min = std::min(m.min, v);
    m.max = std::max(m.max, v);
  }
  m.mean = sum / static_cast<double>(m.n);
  if (m.n > 1) {
    double ss = 0.0;
    for (const double v : values) ss += (v - m.mean) * (v - m.mean);
    m.sd = std::sqrt(ss / static_cast<double>(m.n - 1));
    m.se = m.sd / std::sqrt(static_cast<double>(m.n));
  }
  return m;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (pos - static_cast<double>(lo));
}

Histogram histogram(const std::vector<double>& values, double upper, int bins) {
  Histogram h;
  h.width = upper / bins;
  h.density.assign(static_cast<std::size_t>(bins), 0.0);
  for (int k = 0; k < bins; ++k) h.centres.push_back((k + 0.5) * h.width);
  for (const double v : values) {
    const auto k = static_cast<long>(std::floor(v / h.width));
    if (k >= 0 && k < bins) {
      h.density[static_cast<std::size_t>(k)] += 1.0;
    } else {
      ++h.outside;
    }
  }
  const double scale = values.empty() ? 0.0 : 1.0 / (static_cast<double>(values.size()) * h.width);
  for (auto& d : h.density) d *= scale;
  return h;
}

double ks_exponential(std::vector<double> values, double rate) {
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  double d = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double f = 1.0 - std::exp(-rate * values[i]);
    d = std::max({d, std::abs(f - static_cast<double>(i) / n), std::abs(f - static_cast<double>(i + 1) / n)});
  }
  return d;
}

}  // namespace retreat::experiment
