#include "retreat/physics/ellipse_root.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace retreat::physics {
namespace {

/// F(s) and the bracket's ends of one point.
struct Equation {
  double r0;
  double n0;  ///< r0·z0
  double z1;

  /// F(s) as the bisection computes it: every caller takes the sign from this one expression.
  double f(double s) const noexcept {
    const double ratio0 = n0 / (s + r0);
    const double ratio1 = z1 / (s + 1.0);
    return ratio0 * ratio0 + ratio1 * ratio1 - 1.0;
  }
};

/// The bisection's state: the bracket [s0, s1], the last midpoint s and the halvings made.
struct Bisection {
  static constexpr int max_halvings = 200;
  double s0;
  double s1;
  double s = 0.0;
  int halvings = 0;

  /// Moves to the next midpoint; false when the bisection is over (s is then the root).
  bool next() noexcept {
    if (halvings == max_halvings) {
      return false;
    }
    ++halvings;
    s = 0.5 * (s0 + s1);
    return !(s == s0 || s == s1 || s1 - s0 <= 1e-16 * std::max(1.0, std::abs(s)));
  }

  /// Keeps the half the computed F(s) = @p f points to; false when it is exactly 0 (s is the root).
  bool take_side(double f) noexcept {
    if (f > 0.0) {
      s0 = s;
    } else if (f < 0.0) {
      s1 = s;
    } else {
      return false;
    }
    return true;
  }
};

Bisection start(const Equation& e, double g) {
  return {e.z1 - 1.0, g < 0.0 ? 0.0 : std::hypot(e.n0, e.z1) - 1.0};
}

/// Where every midpoint's computed sign of F is known without computing it: at or left of `lo`
/// it is positive, at or right of `hi` negative.
struct Band {
  double lo;
  double hi;
};

/// The band around the root, or nothing (then every midpoint is evaluated).
///
/// Why a midpoint m ≤ lo needs no evaluation: the computed F, ratio0² + ratio1² − 1, is the exact
/// sum T(m) − 1 with T's relative error at most about 6 ulps (two roundings in each ratio, one in
/// each square, one in the sum; the final subtraction is exact near 1). If the computed F(lo)
/// exceeds 32 ulps of 1, then the exact T(lo) > 1 + 25 ulps; T decreases, so T(m) > T(lo), and
/// the computed T(m) ≥ T(m)·(1 − 6 ulps) > 1: the computed F(m) is positive, as the bisection
/// would find it. The same, mirrored, right of hi.
std::optional<Band> band_around_root(const Equation& e, const Bisection& b) {
  constexpr double margin = 32.0 * std::numeric_limits<double>::epsilon();
  // Newton's method. F is decreasing and convex on s > −1, so from a point left of the root
  // (F ≥ 0) the iterates increase towards it without passing it, and from a point right of it
  // one step lands left of it. It starts at 0 (the root of a point on the ellipse), or at the
  // bracket's left end if that first step leaves the bracket.
  const auto newton_step = [&](double s, double& slope) {
    const double inverse0 = 1.0 / (s + e.r0);
    const double inverse1 = 1.0 / (s + 1.0);
    const double ratio0 = e.n0 * inverse0;
    const double ratio1 = e.z1 * inverse1;
    const double f = ratio0 * ratio0 + ratio1 * ratio1 - 1.0;
    slope = -2.0 * (ratio0 * ratio0 * inverse0 + ratio1 * ratio1 * inverse1);
    return f / slope;
  };
  double slope = 0.0;
  double s = 0.0;
  if (!(s > b.s0 && s < b.s1)) {
    s = b.s0;
  } else {
    s -= newton_step(s, slope);
    if (!(s > b.s0 && s < b.s1)) {
      s = b.s0;
    }
  }
  bool settled = false;
  for (int k = 0; k < 100 && !settled; ++k) {
    const double step = newton_step(s, slope);
    if (!(slope < 0.0)) {
      return std::nullopt;
    }
    s -= step;
    settled = !(std::abs(step) > 1e-9 * std::max(1.0, std::abs(s)));
  }
  if (!settled || !std::isfinite(s)) {
    return std::nullopt;
  }
  // F(root ± t) ≈ ∓|slope|·t: 4 margins away, the ends clear the margin however Newton ended.
  const double tolerance = std::max(4.0 * margin / -slope, 1e-15 * std::max(1.0, std::abs(s)));
  Band band{s - tolerance, s + tolerance};
  // Midpoints lie strictly inside the starting bracket: a band end beyond it decides nothing.
  if (band.lo <= b.s0) {
    band.lo = -std::numeric_limits<double>::infinity();
  } else if (!(e.f(band.lo) > margin)) {
    return std::nullopt;
  }
  if (band.hi >= b.s1) {
    band.hi = std::numeric_limits<double>::infinity();
  } else if (!(e.f(band.hi) < -margin)) {
    return std::nullopt;
  }
  return band;
}

}  // namespace

double ellipse_root_by_bisection(double r0, double z0, double z1, double g) {
  const Equation e{r0, r0 * z0, z1};
  Bisection b = start(e, g);
  while (b.next() && b.take_side(e.f(b.s))) {
  }
  return b.s;
}

double ellipse_root(double r0, double z0, double z1, double g) {
  const Equation e{r0, r0 * z0, z1};
  Bisection b = start(e, g);
  const std::optional<Band> band = band_around_root(e, b);
  if (!band) {
    return ellipse_root_by_bisection(r0, z0, z1, g);
  }
  while (b.next()) {
    // One test, not two: whether s is left or right of the band is a coin toss a branch would
    // mispredict half the time; whether it is inside is not. (A difference of two doubles has
    // the sign of the exact one, so this is lo < s < hi.)
    if (std::min(b.s - band->lo, band->hi - b.s) > 0.0) {
      if (!b.take_side(e.f(b.s))) {
        break;
      }
    } else {
      // Outside the band the computed F(s) is positive left of it and negative right of it
      // (band_around_root says why). Which side comes up is a coin toss: selects, not branches.
      const bool right = b.s >= band->hi;
      b.s0 = right ? b.s0 : b.s;
      b.s1 = right ? b.s : b.s1;
    }
  }
  return b.s;
}

}  // namespace retreat::physics
