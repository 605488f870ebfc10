#pragma once
/// @file
/// Cell lists for fixed-radius neighbour search, linear in the number of points.

#include <cmath>
#include <cstdint>
#include <vector>

#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// The side of square cells over a rectangle of size @p extent: @p min_cell_size, enlarged in
/// steps of 1.25× until there are at most @p max_cells of them.
double cell_size_within(const Vec2& extent, double min_cell_size, double max_cells);

/// A uniform grid over a fixed rectangle, rebuilt from scratch for each snapshot by a counting
/// sort (O(points + cells)). Any two points closer than cell_size() lie in the same or adjacent
/// cells, so a query visits the 3×3 block around a point. Points outside the rectangle are
/// clamped into the border cells, which keeps that property (clamping is 1-Lipschitz per axis).
class NeighbourGrid {
 public:
  /// A grid covering [@p lo, @p hi] with square cells of side at least @p min_cell_size [m].
  /// The cell side is enlarged if needed so that there are at most @p max_cells cells.
  NeighbourGrid(const Vec2& lo, const Vec2& hi, double min_cell_size,
                std::size_t max_cells = std::size_t{1} << 22);

  /// Side of a cell: the largest query radius this grid answers exactly [m].
  double cell_size() const noexcept { return cell_; }

  /// Sorts @p points (held by reference until the next build) into cells.
  void build(const std::vector<Vec2>& points);

  /// Calls @p visit(index) for every built point in the 3×3 cells around @p p, including p's own
  /// index if p is one of the points. The caller filters by distance.
  template <class Visit>
  void for_each_candidate(const Vec2& p, Visit&& visit) const {
    const int cx = cell_x(p.x());
    const int cy = cell_y(p.y());
    const int x0 = cx > 0 ? cx - 1 : 0;
    const int x1 = cx + 1 < nx_ ? cx + 1 : nx_ - 1;
    const int y0 = cy > 0 ? cy - 1 : 0;
    const int y1 = cy + 1 < ny_ ? cy + 1 : ny_ - 1;
    for (int y = y0; y <= y1; ++y) {
      // Cells of one row are contiguous, so a row of the block is one contiguous index range.
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_);
      const std::uint32_t begin = start_[row + static_cast<std::size_t>(x0)];
      const std::uint32_t end = start_[row + static_cast<std::size_t>(x1) + 1];
      for (std::uint32_t k = begin; k < end; ++k) {
        visit(order_[k]);
      }
    }
  }

 private:
  // In the header: every query and every build calls them, once per point and axis.
  // The cell of a coordinate c cells from the grid's low edge, clamped to [0, n − 1]: floor(c)
  // without std::floor, which the x86-64 baseline has no instruction for (GCC inlines a
  // round trip through an integer, about 20 cycles on the tick's path). c < 1 is cell 0;
  // c ≥ n − 1 (an integer) is the last cell; between them c is positive, so truncation is floor.
  static int cell_of(double c, int n) noexcept {
    return !(c >= 1.0) ? 0 : (c >= n - 1 ? n - 1 : static_cast<int>(c));
  }
  int cell_x(double x) const noexcept { return cell_of((x - lo_.x()) * inv_cell_, nx_); }
  int cell_y(double y) const noexcept { return cell_of((y - lo_.y()) * inv_cell_, ny_); }

  Vec2 lo_;
  double cell_ = 1.0;
  double inv_cell_ = 1.0;
  int nx_ = 1;
  int ny_ = 1;
  std::vector<std::uint32_t> start_;  // nx·ny + 1 offsets into order_
  std::vector<std::uint32_t> order_;  // point indices sorted by cell
  std::vector<std::uint32_t> cell_of_;
  std::vector<std::uint32_t> scratch_;
};

}  // namespace retreat::physics
