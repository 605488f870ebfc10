#pragma once
/// @file
/// The domain D: an axis-aligned ellipse or rectangle centred on the origin.

#include "retreat/core/rng.hpp"
#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// The point of ∂D nearest to a query point.
struct BoundaryPoint {
  Vec2 point;              ///< nearest point of ∂D [m]
  Vec2 outward_normal;     ///< unit outward normal of ∂D at that point (for an outside query at a
                           ///< rectangle corner: the unit vector from the corner to the query)
  double signed_distance;  ///< distance to ∂D, negative inside D [m]
};

/// A convex domain. Cheap to copy. All lengths in metres.
class Domain {
 public:
  /// Ellipse x²/a² + y²/b² ≤ 1. Precondition: a, b > 0.
  static Domain ellipse(double semi_axis_x, double semi_axis_y);
  /// Rectangle |x| ≤ w/2, |y| ≤ h/2. Precondition: w, h > 0.
  static Domain rectangle(double width, double height);

  bool is_ellipse() const noexcept { return ellipse_; }
  /// Half extents of the bounding box: (a, b) or (w/2, h/2) [m].
  const Vec2& half_extent() const noexcept { return half_; }

  /// |D| [m²].
  double area() const noexcept { return area_; }
  /// Length of ∂D [m].
  double perimeter() const noexcept { return perimeter_; }
  /// Area of the inner parallel set {p : signed_distance(p) ≤ −inset} [m²] (0 if empty).
  double inset_area(double inset) const;

  /// True if @p p is in the closed domain.
  bool contains(const Vec2& p) const noexcept;
  /// Euclidean signed distance to ∂D (negative inside) [m].
  double signed_distance(const Vec2& p) const { return nearest_boundary_point(p).signed_distance; }
  /// A lower bound of the distance from an inside point @p p to ∂D, O(1) and exact for the
  /// rectangle; returns 0 for points outside. Used to skip the exact ellipse distance when a
  /// robot is far from the boundary.
  double clearance_lower_bound(const Vec2& p) const noexcept;
  /// Nearest boundary point, outward normal, signed distance. For the ellipse: Eberly's robust
  /// root finding ("Distance from a point to an ellipse", 2013), accurate to rounding.
  BoundaryPoint nearest_boundary_point(const Vec2& p) const;

  /// A point uniform on D.
  Vec2 sample_uniform(Rng& rng) const;
  /// A point uniform on the inner parallel set {signed_distance ≤ −inset} (rejection from D).
  /// Precondition: inset_area(inset) > 0.
  Vec2 sample_inset(Rng& rng, double inset) const;
  /// A point uniform on ∂D by arc length, with its outward normal.
  BoundaryPoint sample_boundary(Rng& rng) const;

 private:
  Domain(bool is_ellipse, Vec2 half);
  bool ellipse_ = true;
  Vec2 half_{1.0, 1.0};
  double area_ = 0.0;
  double perimeter_ = 0.0;
};

}  // namespace retreat::physics
