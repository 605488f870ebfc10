#include "retreat/physics/barrier_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace retreat::physics {
namespace {

/// Smallest d > d_min with f(d) >= 0 for an f that is negative at d_min and increasing once it
/// turns positive (both terms of B below are convex in d, minus a linear term).
double first_root(const std::function<double(double)>& f, double d_min) {
  double lo = d_min;
  double hi = std::max(2.0 * d_min, 1e-3);
  while (f(hi) < 0.0) {
    lo = hi;
    hi *= 2.0;
  }
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 0.0 ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

BarrierCertificate::BarrierCertificate(const BarrierParams& params) : params_(params) {
  const double l = params_.projection_distance;
  const double ds = params_.safety_distance;
  u_max_ = std::hypot(params_.max_speed, l * params_.max_turn_rate);
  // A pairwise constraint with normal of length at most 2d can only bind while
  // B(d² − D_s²) < 2d·speed. B = min(cubic, linear): it reaches 2d·speed where both do.
  const auto reach = [&](double speed) {
    const double cubic = first_root(
        [&](double d) {
          const double h = d * d - ds * ds;
          return 0.5 * params_.gamma * h * h * h - 2.0 * d * speed;
        },
        ds);
    const double linear = first_root(
        [&](double d) { return (d * d - ds * ds) / (4.0 * params_.dt) - 2.0 * d * speed; }, ds);
    return std::max(cubic, linear) * (1.0 + 1e-9);
  };
  // The safety constraint acts on centres with |v| ≤ max_speed; the steering constraint on
  // projected points with |u| ≤ u_max, and centres are at most 2l farther apart than those.
  range_ = std::max(reach(params_.max_speed), reach(u_max_) + 2.0 * l);
}

double BarrierCertificate::barrier_bound(double h) const noexcept {
  if (!(h > 0.0)) {
    return 0.0;
  }
  return std::min(0.5 * params_.gamma * h * h * h, h / (4.0 * params_.dt));
}

void BarrierCertificate::add_limits(std::vector<HalfPlane>& out, const Vec2& e) const {
  const Vec2 n(-e.y(), e.x());
  const double lateral = params_.projection_distance * params_.max_turn_rate;
  out.push_back({e, params_.max_speed});
  out.push_back({-e, params_.max_speed});
  out.push_back({n, lateral});
  out.push_back({-n, lateral});
}

void BarrierCertificate::add_neighbour(std::vector<HalfPlane>& out, const SensedBody& self,
                                       const SensedBody& other) const {
  const double ds2 = params_.safety_distance * params_.safety_distance;
  // Steering: −2(q_i − q_j)ᵀu ≤ B(h_q).
  const Vec2 dq = self.q - other.q;
  const double dq2 = dq.squaredNorm();
  const double bq = barrier_bound(dq2 - ds2);
  if (bq < 2.0 * std::sqrt(dq2) * u_max_) {
    out.push_back({-2.0 * dq, bq});
  }
  // Safety: −2((p_i − p_j)ᵀe_i)·e_iᵀu ≤ B(h_c); only v = e_iᵀu moves the centre.
  const Vec2 dp = self.p - other.p;
  const double s = dp.dot(self.e);
  const double bc = barrier_bound(dp.squaredNorm() - ds2);
  if (bc < 2.0 * std::abs(s) * params_.max_speed) {
    out.push_back({-2.0 * s * self.e, bc});
  }
}

void BarrierCertificate::add_boundary(std::vector<HalfPlane>& out, const Vec2& outward_normal,
                                      double clearance) const {
  const double b = params_.boundary_gain * clearance;
  if (b < u_max_) {
    out.push_back({outward_normal, b});
  }
}

UnicycleCommand BarrierCertificate::to_command(const SensedBody& self, const Vec2& u) const {
  return to_unicycle_command(self.e, u, params_.projection_distance);
}

}  // namespace retreat::physics
