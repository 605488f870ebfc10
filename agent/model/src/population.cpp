#include "retreat/model/population.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace retreat::model {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

/// Binomial(n, q) probabilities, k = 0..n.
std::vector<double> binomial(std::uint32_t n, double q) {
  std::vector<double> p(n + 1, 0.0);
  if (q <= 0.0) {
    p[0] = 1.0;
    return p;
  }
  if (q >= 1.0) {
    p[n] = 1.0;
    return p;
  }
  // p[k] = C(n, k) q^k (1 − q)^(n − k), by the ratio p[k+1]/p[k] = (n − k)/(k + 1) · q/(1 − q).
  p[0] = std::pow(1.0 - q, n);
  for (std::uint32_t k = 0; k < n; ++k) {
    p[k + 1] = p[k] * static_cast<double>(n - k) / static_cast<double>(k + 1) * q / (1.0 - q);
  }
  return p;
}

}  // namespace

std::vector<double> poisson_weights(double mean) {
  require(std::isfinite(mean) && mean >= 0.0,
          "Poisson mean = " + std::to_string(mean) + ": must be finite and >= 0");
  std::vector<double> w;
  // log-space start avoids underflow of e^(−mean) for large means.
  for (std::size_t y = 0;; ++y) {
    const double yd = static_cast<double>(y);
    const double p = mean > 0.0 ? std::exp(yd * std::log(mean) - mean - std::lgamma(yd + 1.0)) : (y == 0 ? 1.0 : 0.0);
    w.push_back(p);
    if (yd > mean && p < 1e-15) break;
  }
  return w;
}

std::vector<double> expected_population(const PopulationChain& chain, double duration) {
  require(std::isfinite(chain.dt) && chain.dt > 0.0, "dt = " + std::to_string(chain.dt) + ": must be finite and > 0");
  require(std::isfinite(duration) && duration > 0.0,
          "duration = " + std::to_string(duration) + ": must be finite and > 0");
  require(std::isfinite(chain.arrival_rate) && chain.arrival_rate >= 0.0,
          "arrival_rate = " + std::to_string(chain.arrival_rate) + ": must be finite and >= 0");
  for (const double q : chain.leave_per_step) {
    require(q >= 0.0 && q <= 1.0, "leave_per_step = " + std::to_string(q) + ": must be in [0, 1]");
  }
  const std::uint32_t cap = std::max(chain.max_robots, chain.initial);
  std::vector<double> p(cap + 1, 0.0), next(cap + 1, 0.0);
  p[chain.initial] = 1.0;
  const auto leave = [&](std::uint32_t n) {
    return n < chain.leave_per_step.size() ? chain.leave_per_step[n] : 0.0;
  };
  std::vector<std::vector<double>> departures(cap + 1);  // Binomial(n, leave(n)), cached
  for (std::uint32_t n = 0; n <= cap; ++n) departures[n] = binomial(n, leave(n));
  const auto arrivals = poisson_weights(chain.arrival_rate * chain.dt);

  const auto steps = static_cast<std::size_t>(std::floor(duration / chain.dt + 1e-9));
  std::vector<double> mean;
  mean.reserve(steps + 1);
  const auto expectation = [&] {
    double m = 0.0;
    for (std::uint32_t n = 0; n <= cap; ++n) m += static_cast<double>(n) * p[n];
    return m;
  };
  mean.push_back(expectation());
  std::size_t next_arrival = 0;
  for (std::size_t k = 1; k <= steps; ++k) {
    const double t = static_cast<double>(k) * chain.dt;
    // Deterministic arrivals in (t − dt, t].
    while (next_arrival < chain.arrival_times.size() && chain.arrival_times[next_arrival] <= t + 1e-9) {
      std::fill(next.begin(), next.end(), 0.0);
      for (std::uint32_t n = 0; n <= cap; ++n) next[std::min(n + 1, cap)] += p[n];
      p.swap(next);
      ++next_arrival;
    }
    // Poisson arrivals.
    if (chain.arrival_rate > 0.0) {
      std::fill(next.begin(), next.end(), 0.0);
      for (std::uint32_t n = 0; n <= cap; ++n) {
        if (p[n] == 0.0) continue;
        for (std::size_t a = 0; a < arrivals.size(); ++a) {
          next[std::min<std::size_t>(n + a, cap)] += p[n] * arrivals[a];
        }
      }
      p.swap(next);
    }
    // Departures.
    if (t + 1e-9 >= chain.first_decision) {
      std::fill(next.begin(), next.end(), 0.0);
      for (std::uint32_t n = 0; n <= cap; ++n) {
        if (p[n] == 0.0) continue;
        const auto& d = departures[n];
        for (std::uint32_t gone = 0; gone <= n; ++gone) next[n - gone] += p[n] * d[gone];
      }
      p.swap(next);
    }
    mean.push_back(expectation());
  }
  return mean;
}

double time_mean(const std::vector<double>& series, double dt, double from, double to) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const double t = static_cast<double>(k) * dt;
    if (t + 1e-9 < from || t > to + 1e-9) continue;
    sum += series[k];
    ++n;
  }
  return n > 0 ? sum / static_cast<double>(n) : std::nan("");
}

}  // namespace retreat::model
