#include "retreat/physics/placement.hpp"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace retreat::physics {

std::vector<Pose> place_robots(const Domain& domain, std::size_t count, double walk_inset,
                               double projection_distance, double min_separation, Rng& rng) {
  std::vector<Pose> poses;
  poses.reserve(count);
  // Hash grid of accepted centres, cell = min_separation: conflicts lie in the 3×3 block.
  const double cell = min_separation;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;
  const auto key = [](std::int64_t x, std::int64_t y) { return x * 1000003LL + y; };
  const auto cell_of = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell)); };
  const std::size_t max_attempts = 10000 * (count + 1);
  std::size_t attempts = 0;
  while (poses.size() < count) {
    if (++attempts > max_attempts) {
      throw std::logic_error("place_robots: could not place " + std::to_string(count) +
                             " robots without overlap");
    }
    const Vec2 q = domain.sample_inset(rng, walk_inset);
    const double theta = rng.angle();
    const Vec2 p = q - projection_distance * heading(theta);
    const std::int64_t cx = cell_of(p.x());
    const std::int64_t cy = cell_of(p.y());
    bool free = true;
    for (std::int64_t y = cy - 1; y <= cy + 1 && free; ++y) {
      for (std::int64_t x = cx - 1; x <= cx + 1 && free; ++x) {
        const auto found = cells.find(key(x, y));
        if (found == cells.end()) {
          continue;
        }
        for (const std::uint32_t k : found->second) {
          if ((poses[k].position - p).squaredNorm() < min_separation * min_separation) {
            free = false;
            break;
          }
        }
      }
    }
    if (!free) {
      continue;
    }
    cells[key(cx, cy)].push_back(static_cast<std::uint32_t>(poses.size()));
    poses.push_back({p, theta});
  }
  return poses;
}

}  // namespace retreat::physics
