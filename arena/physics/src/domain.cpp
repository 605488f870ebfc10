#include "retreat/physics/domain.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/physics/ellipse_root.hpp"

namespace retreat::physics {
namespace {

constexpr double pi = 3.14159265358979323846;

double sign_of(double x) { return x < 0.0 ? -1.0 : 1.0; }

/// Nearest point of the ellipse with semi-axes e0 ≥ e1 to (y0, y1) in the closed first quadrant.
Vec2 nearest_on_ellipse_quadrant(double e0, double e1, double y0, double y1) {
  if (y1 > 0.0) {
    if (y0 > 0.0) {
      const double z0 = y0 / e0;
      const double z1 = y1 / e1;
      const double g = z0 * z0 + z1 * z1 - 1.0;
      if (g == 0.0) {
        return {y0, y1};
      }
      const double r0 = (e0 / e1) * (e0 / e1);
      const double s = ellipse_root(r0, z0, z1, g);
      return {r0 * y0 / (s + r0), y1 / (s + 1.0)};
    }
    return {0.0, e1};
  }
  const double numer0 = e0 * y0;
  const double denom0 = e0 * e0 - e1 * e1;
  if (numer0 < denom0) {
    const double xde0 = numer0 / denom0;
    return {e0 * xde0, e1 * std::sqrt(std::max(0.0, 1.0 - xde0 * xde0))};
  }
  return {e0, 0.0};
}

}  // namespace

Domain::Domain(bool is_ellipse, Vec2 half) : ellipse_(is_ellipse), half_(std::move(half)) {
  const double a = half_.x();
  const double b = half_.y();
  if (ellipse_) {
    area_ = pi * a * b;
    // Trapezoidal rule on a smooth periodic integrand converges geometrically.
    constexpr int n = 4096;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
      const double t = 2.0 * pi * k / n;
      sum += std::hypot(a * std::sin(t), b * std::cos(t));
    }
    perimeter_ = sum * 2.0 * pi / n;
  } else {
    area_ = 4.0 * a * b;
    perimeter_ = 4.0 * (a + b);
  }
}

Domain Domain::ellipse(double semi_axis_x, double semi_axis_y) {
  return Domain(true, Vec2(semi_axis_x, semi_axis_y));
}

Domain Domain::rectangle(double width, double height) {
  return Domain(false, Vec2(0.5 * width, 0.5 * height));
}

double Domain::inset_area(double inset) const {
  const double a = half_.x();
  const double b = half_.y();
  if (inset <= 0.0) {
    return area_;
  }
  if (!ellipse_) {
    return std::max(0.0, 2.0 * (a - inset)) * std::max(0.0, 2.0 * (b - inset));
  }
  const double lo = std::min(a, b);
  const double hi = std::max(a, b);
  if (inset >= lo) {
    return 0.0;
  }
  if (inset <= lo * lo / hi) {
    // Steiner: up to the least radius of curvature b²/a the inner parallel set is a Minkowski
    // summand of D, so |D| = |D_i| + per(D_i)·i + π i² with per(D_i) = per(D) − 2π i.
    return area_ - perimeter_ * inset + pi * inset * inset;
  }
  // Past the least radius of curvature: midpoint rule on a 400 × 400 grid (rare; validation of
  // very elongated ellipses only).
  constexpr int n = 400;
  const double hx = 2.0 * a / n;
  const double hy = 2.0 * b / n;
  std::size_t inside = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Vec2 p(-a + (i + 0.5) * hx, -b + (j + 0.5) * hy);
      if (clearance_lower_bound(p) >= inset || signed_distance(p) <= -inset) {
        ++inside;
      }
    }
  }
  return static_cast<double>(inside) * hx * hy;
}

bool Domain::contains(const Vec2& p) const noexcept {
  if (ellipse_) {
    const double x = p.x() / half_.x();
    const double y = p.y() / half_.y();
    return x * x + y * y <= 1.0;
  }
  return std::abs(p.x()) <= half_.x() && std::abs(p.y()) <= half_.y();
}

double Domain::clearance_lower_bound(const Vec2& p) const noexcept {
  if (!ellipse_) {
    return std::max(0.0, std::min(half_.x() - std::abs(p.x()), half_.y() - std::abs(p.y())));
  }
  // p lies on the boundary of s·D, s = √g. Since D contains the disc of radius min(a, b) about
  // the origin and is convex, s·D + (1 − s)·disc ⊆ D: p is at least (1 − s)·min(a, b) inside.
  const double x = p.x() / half_.x();
  const double y = p.y() / half_.y();
  const double g = x * x + y * y;
  if (g >= 1.0) {
    return 0.0;
  }
  return (1.0 - std::sqrt(g)) * std::min(half_.x(), half_.y());
}

BoundaryPoint Domain::nearest_boundary_point(const Vec2& p) const {
  BoundaryPoint out;
  if (!ellipse_) {
    const double hx = half_.x();
    const double hy = half_.y();
    const double dx = std::abs(p.x()) - hx;
    const double dy = std::abs(p.y()) - hy;
    if (dx <= 0.0 && dy <= 0.0) {
      if (dx >= dy) {
        out.point = Vec2(sign_of(p.x()) * hx, p.y());
        out.outward_normal = Vec2(sign_of(p.x()), 0.0);
        out.signed_distance = dx;
      } else {
        out.point = Vec2(p.x(), sign_of(p.y()) * hy);
        out.outward_normal = Vec2(0.0, sign_of(p.y()));
        out.signed_distance = dy;
      }
      return out;
    }
    out.point = Vec2(std::clamp(p.x(), -hx, hx), std::clamp(p.y(), -hy, hy));
    const Vec2 diff = p - out.point;
    out.signed_distance = diff.norm();
    out.outward_normal = diff / out.signed_distance;
    return out;
  }
  // Ellipse: fold into the first quadrant with the longer axis first.
  const bool swap = half_.x() < half_.y();
  const double e0 = swap ? half_.y() : half_.x();
  const double e1 = swap ? half_.x() : half_.y();
  const double u = swap ? p.y() : p.x();
  const double w = swap ? p.x() : p.y();
  const Vec2 folded = nearest_on_ellipse_quadrant(e0, e1, std::abs(u), std::abs(w));
  const double nx = sign_of(u) * folded.x();
  const double ny = sign_of(w) * folded.y();
  out.point = swap ? Vec2(ny, nx) : Vec2(nx, ny);
  const double a = half_.x();
  const double b = half_.y();
  out.outward_normal = Vec2(out.point.x() / (a * a), out.point.y() / (b * b)).normalized();
  const double distance = (p - out.point).norm();
  out.signed_distance = contains(p) ? -distance : distance;
  return out;
}

Vec2 Domain::sample_uniform(Rng& rng) const {
  if (ellipse_) {
    // The affine image of a uniform point of the unit disc is uniform on the ellipse.
    const double radius = std::sqrt(rng.uniform());
    const double angle = rng.angle();
    return {half_.x() * radius * std::cos(angle), half_.y() * radius * std::sin(angle)};
  }
  const double x = rng.uniform(-half_.x(), half_.x());
  const double y = rng.uniform(-half_.y(), half_.y());
  return {x, y};
}

Vec2 Domain::sample_inset(Rng& rng, double inset) const {
  for (;;) {
    const Vec2 p = sample_uniform(rng);
    if (clearance_lower_bound(p) >= inset || signed_distance(p) <= -inset) {
      return p;
    }
  }
}

BoundaryPoint Domain::sample_boundary(Rng& rng) const {
  BoundaryPoint out;
  out.signed_distance = 0.0;
  const double a = half_.x();
  const double b = half_.y();
  if (ellipse_) {
    // Parameter t with density ∝ |γ'(t)| = √(a² sin²t + b² cos²t) by rejection.
    const double bound = std::max(a, b);
    for (;;) {
      const double t = rng.angle();
      const double speed = std::hypot(a * std::sin(t), b * std::cos(t));
      if (rng.uniform() * bound <= speed) {
        out.point = Vec2(a * std::cos(t), b * std::sin(t));
        out.outward_normal = Vec2(std::cos(t) / a, std::sin(t) / b).normalized();
        return out;
      }
    }
  }
  double s = rng.uniform() * perimeter_;
  if (s < 2.0 * a) {
    out.point = Vec2(-a + s, -b);
    out.outward_normal = Vec2(0.0, -1.0);
    return out;
  }
  s -= 2.0 * a;
  if (s < 2.0 * b) {
    out.point = Vec2(a, -b + s);
    out.outward_normal = Vec2(1.0, 0.0);
    return out;
  }
  s -= 2.0 * b;
  if (s < 2.0 * a) {
    out.point = Vec2(a - s, b);
    out.outward_normal = Vec2(0.0, 1.0);
    return out;
  }
  s -= 2.0 * a;
  out.point = Vec2(-a, b - std::min(s, 2.0 * b));
  out.outward_normal = Vec2(-1.0, 0.0);
  return out;
}

}  // namespace retreat::physics
