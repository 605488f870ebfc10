#include "retreat/physics/collection_task.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/physics/neighbour_grid.hpp"

namespace retreat::physics {

CollectionTask::CollectionTask(const Domain& domain, double lambda_p, double lambda_d, double delta,
                               Rng& world_rng)
    : domain_(domain), delta_(delta) {
  init(pickups_, static_cast<std::size_t>(std::llround(lambda_p * domain.area())), lambda_p,
       world_rng);
  init(dropoffs_, static_cast<std::size_t>(std::llround(lambda_d * domain.area())), lambda_d,
       world_rng);
}

void CollectionTask::init(PointSet& set, std::size_t count, double density, Rng& rng) const {
  // Cells of side ≥ 2δ: a δ-disc touches at most a 2×2 block, visited as the 3×3 around it.
  // Larger cells where points are sparse keep the index small (about one point per cell).
  // At most max(64, 2·count) cells, whatever the arena's size: a query's answer does not depend
  // on the cell size (any side >= 2δ), only the index's memory does.
  const Vec2& half = domain_.half_extent();
  const double sparse_cell = density > 0.0 ? 1.0 / std::sqrt(density) : 1.0;
  set.cell = cell_size_within(2.0 * half, std::max(2.0 * delta_, sparse_cell),
                              std::max(64.0, 2.0 * static_cast<double>(count)));
  set.nx = std::max(1, static_cast<int>(std::ceil(2.0 * half.x() / set.cell)));
  set.ny = std::max(1, static_cast<int>(std::ceil(2.0 * half.y() / set.cell)));
  set.cells.assign(static_cast<std::size_t>(set.nx) * static_cast<std::size_t>(set.ny), {});
  set.points.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    set.points[i] = domain_.sample_uniform(rng);
    set.insert(static_cast<std::uint32_t>(i));
  }
}

std::size_t CollectionTask::PointSet::cell_index(const Vec2& p) const {
  // The grid's lower-left corner is −half_extent = −(nx·cell)/2 rounded; clamp into the grid.
  const double x0 = -0.5 * nx * cell;
  const double y0 = -0.5 * ny * cell;
  const int cx = std::clamp(static_cast<int>(std::floor((p.x() - x0) / cell)), 0, nx - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((p.y() - y0) / cell)), 0, ny - 1);
  return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(cx);
}

void CollectionTask::PointSet::insert(std::uint32_t index) {
  cells[cell_index(points[index])].push_back(index);
}

void CollectionTask::PointSet::erase(std::uint32_t index) {
  auto& cell_points = cells[cell_index(points[index])];
  cell_points.erase(std::find(cell_points.begin(), cell_points.end(), index));
}

long CollectionTask::PointSet::nearest_within(const Vec2& p, double radius) const {
  // Nearest wins; ties go to the lower index, so the choice does not depend on visiting order.
  const auto closer = [&](std::uint32_t k, long best, double best_d2, double d2) {
    return d2 <= radius * radius && (best < 0 || d2 < best_d2 || (d2 == best_d2 && static_cast<long>(k) < best));
  };
  if (points.size() <= few_points) {
    // A handful of locations (the paper's arena holds four of each): all of them, a superset of
    // the 3×3 cells' points, is cheaper than finding the cells, and gives the same answer.
    long best = -1;
    double best_d2 = 0.0;
    for (std::uint32_t k = 0; k < points.size(); ++k) {
      const double d2 = (points[k] - p).squaredNorm();
      if (closer(k, best, best_d2, d2)) {
        best_d2 = d2;
        best = static_cast<long>(k);
      }
    }
    return best;
  }
  const double x0 = -0.5 * nx * cell;
  const double y0 = -0.5 * ny * cell;
  const int cx = std::clamp(static_cast<int>(std::floor((p.x() - x0) / cell)), 0, nx - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((p.y() - y0) / cell)), 0, ny - 1);
  long best = -1;
  double best_d2 = 0.0;
  for (int y = std::max(0, cy - 1); y <= std::min(ny - 1, cy + 1); ++y) {
    for (int x = std::max(0, cx - 1); x <= std::min(nx - 1, cx + 1); ++x) {
      for (const std::uint32_t k :
           cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx) +
                 static_cast<std::size_t>(x)]) {
        const double d2 = (points[k] - p).squaredNorm();
        if (closer(k, best, best_d2, d2)) {
          best_d2 = d2;
          best = static_cast<long>(k);
        }
      }
    }
  }
  return best;
}

bool CollectionTask::try_pick_up(const Vec2& p, Rng& world_rng) {
  const long found = pickups_.nearest_within(p, delta_);
  if (found < 0) {
    return false;
  }
  const auto index = static_cast<std::uint32_t>(found);
  pickups_.erase(index);
  pickups_.points[index] = domain_.sample_uniform(world_rng);
  pickups_.insert(index);
  return true;
}

bool CollectionTask::can_drop_off(const Vec2& p) const {
  return dropoffs_.nearest_within(p, delta_) >= 0;
}

}  // namespace retreat::physics
