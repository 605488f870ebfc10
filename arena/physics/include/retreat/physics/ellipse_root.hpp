#pragma once
/// @file
/// The root behind the nearest point of an ellipse (Domain::nearest_boundary_point): with the
/// point folded into the first quadrant and scaled, z = (y0/e0, y1/e1), r0 = (e0/e1)², the root
/// of the decreasing function
///
///   F(s) = (r0·z0 / (s + r0))² + (z1 / (s + 1))² − 1,   s > −1,
///
/// bracketed by [z1 − 1, |(r0·z0, z1)| − 1] (or [z1 − 1, 0] inside the ellipse, g < 0).
///
/// Every trajectory of the physical world goes through this number, so it is defined by one
/// algorithm, bisection on doubles (Eberly 2013, "Distance from a point to an ellipse"):
/// ellipse_root_by_bisection. ellipse_root returns the same double, bit for bit, faster; its
/// unit test compares the two on millions of points.

namespace retreat::physics {

/// The root by bisection, every midpoint's side taken from the computed sign of F there; stops
/// when a midpoint repeats an end, the bracket is 1e-16 · max(1, |s|) wide, F is 0 or after 200
/// halvings. The definition; @p g = z0² + z1² − 1 (< 0 inside the ellipse).
double ellipse_root_by_bisection(double r0, double z0, double z1, double g);

/// The same double as ellipse_root_by_bisection, computed faster: Newton's method first finds
/// the root to about 1e-15, and a band around it is checked: F's computed sign at the band's two
/// ends must be beyond any rounding error of F (32 ulps of 1). Then the same bisection runs, but
/// a midpoint outside the band takes its side from where it lies (F is decreasing, and the check
/// proves the computed sign there could not differ); only the midpoints inside the band (about
/// 10 of some 50) evaluate F. If Newton does not settle or the check fails, this is
/// ellipse_root_by_bisection.
double ellipse_root(double r0, double z0, double z1, double g);

}  // namespace retreat::physics
