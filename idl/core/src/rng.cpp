#include "retreat/core/rng.hpp"

#include <cmath>

#include "retreat/core/seed.hpp"

namespace retreat {

Rng::Rng(std::uint64_t seed) noexcept {
  for (std::size_t k = 0; k < s_.size(); ++k) {
    s_[k] = retreat::splitmix64(seed + k * 0x9E3779B97F4A7C15ULL);
  }
  if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0) {
    s_[0] = 1;  // the all-zero state is the one fixed point of xoshiro
  }
}

double Rng::angle() noexcept {
  constexpr double pi = 3.14159265358979323846;
  return uniform(-pi, pi);
}

double Rng::exponential(double rate) noexcept {
  if (!(rate > 0.0)) {
    return HUGE_VAL;
  }
  return -std::log1p(-uniform()) / rate;
}

namespace {

constexpr double poisson_chunk = 30.0;  ///< exp(−30) is far from underflow

/// Poisson(@p mean) by sequential search, given @p exp_minus_mean = exp(−mean), mean <= 30.
std::uint64_t poisson_by_inversion(Rng& rng, double mean, double exp_minus_mean) noexcept {
  double p = exp_minus_mean;
  double cdf = p;
  const double u = rng.uniform();
  std::uint64_t k = 0;
  while (u > cdf && k < 1000) {
    ++k;
    p *= mean / static_cast<double>(k);
    cdf += p;
  }
  return k;
}

}  // namespace

std::uint64_t Rng::poisson(double mean) noexcept { return PoissonDraw(mean)(*this); }

PoissonDraw::PoissonDraw(double mean) noexcept {
  // Inversion in chunks of mean <= 30 so that exp(−mean) never underflows (a sum of independent
  // Poisson variables is Poisson): 30, 30, …, then what is left, if anything.
  while (mean > poisson_chunk) {
    ++full_chunks_;
    mean -= poisson_chunk;
  }
  if (mean > 0.0) {
    last_ = mean;
    exp_last_ = std::exp(-mean);
  }
}

std::uint64_t PoissonDraw::operator()(Rng& rng) const noexcept {
  static const double exp_minus_chunk = std::exp(-poisson_chunk);
  std::uint64_t total = 0;
  for (std::uint64_t c = 0; c < full_chunks_; ++c) total += poisson_by_inversion(rng, poisson_chunk, exp_minus_chunk);
  if (last_ > 0.0) total += poisson_by_inversion(rng, last_, exp_last_);
  return total;
}

}  // namespace retreat
