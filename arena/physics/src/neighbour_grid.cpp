#include "retreat/physics/neighbour_grid.hpp"

#include <algorithm>
#include <cmath>

namespace retreat::physics {

double cell_size_within(const Vec2& extent, double min_cell_size, double max_cells) {
  double cell = min_cell_size;
  while (std::ceil(extent.x() / cell) * std::ceil(extent.y() / cell) > max_cells) {
    cell *= 1.25;
  }
  return cell;
}

NeighbourGrid::NeighbourGrid(const Vec2& lo, const Vec2& hi, double min_cell_size,
                             std::size_t max_cells)
    : lo_(lo) {
  const Vec2 extent = (hi - lo).cwiseMax(Vec2::Constant(1e-9));
  cell_ = cell_size_within(extent, min_cell_size, static_cast<double>(max_cells));
  inv_cell_ = 1.0 / cell_;
  nx_ = std::max(1, static_cast<int>(std::ceil(extent.x() / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(extent.y() / cell_)));
  start_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_) + 1, 0);
}

void NeighbourGrid::build(const std::vector<Vec2>& points) {
  const std::size_t n = points.size();
  std::fill(start_.begin(), start_.end(), 0);
  cell_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t cell =
        static_cast<std::uint32_t>(cell_y(points[i].y()) * nx_ + cell_x(points[i].x()));
    cell_of_[i] = cell;
    ++start_[cell + 1];
  }
  for (std::size_t c = 1; c < start_.size(); ++c) {
    start_[c] += start_[c - 1];
  }
  order_.resize(n);
  // Stable fill: within a cell, points keep ascending index order (deterministic iteration).
  std::vector<std::uint32_t>& next = scratch_;
  next.assign(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    order_[next[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }
}

}  // namespace retreat::physics
