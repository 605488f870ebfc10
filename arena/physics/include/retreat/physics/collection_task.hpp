#pragma once
/// @file
/// The distributed collection task (MODEL.md §2.5, §3): pick-up and drop-off locations in D, a
/// free robot within δ of a pick-up location becomes loaded, a loaded robot within δ of a
/// drop-off location delivers.
///
/// Decisions where the paper is silent:
///  - Counts: round(λ_p·|D|) and round(λ_d·|D|) locations, each uniform on D: a Poisson process
///    conditioned on its mean count. The model uses the density itself, so the run-to-run
///    fluctuation of a Poisson count (±1/√(λ|D|), 11 % at 82 points) is noise it does not have.
///  - A used pick-up location (an object taken) is replaced at once by a new uniform one, so the
///    density stays λ_p and the points ahead of a robot stay a fresh Poisson field, as the rate
///    Ω_p = 2δvλ_p assumes. Drop-off locations are depots: they persist and accept any number of
///    deliveries (the paper: objects "can be dropped off at any of the drop-off locations").
///  - Locations are uniform on all of D, although robot centres stay r inside ∂D; a location
///    within δ − r of ∂D is harder to reach (an edge effect of order perimeter·δ/|D|).

#include <vector>

#include "retreat/physics/domain.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// Pick-up and drop-off locations with a cell index for O(1) "anything within δ?" queries.
class CollectionTask {
 public:
  /// Draws the locations from @p world_rng. Preconditions: λ_p, λ_d ≥ 0, δ > 0.
  CollectionTask(const Domain& domain, double lambda_p, double lambda_d, double delta,
                 Rng& world_rng);

  /// If a pick-up location lies within δ of @p p, takes the nearest one, replaces it by a new
  /// uniform location drawn from @p world_rng and returns true.
  bool try_pick_up(const Vec2& p, Rng& world_rng);

  /// True if a drop-off location lies within δ of @p p.
  bool can_drop_off(const Vec2& p) const;

  const std::vector<Vec2>& pickups() const noexcept { return pickups_.points; }
  const std::vector<Vec2>& dropoffs() const noexcept { return dropoffs_.points; }

 private:
  struct PointSet {
    std::vector<Vec2> points;
    std::vector<std::vector<std::uint32_t>> cells;
    int nx = 1;
    int ny = 1;
    double cell = 1.0;
    std::size_t cell_index(const Vec2& p) const;
    void insert(std::uint32_t index);
    void erase(std::uint32_t index);
    // Index of the nearest point within radius of p, or -1.
    long nearest_within(const Vec2& p, double radius) const;
    // Up to this many points a query looks at every one rather than at the cells around p.
    static constexpr std::size_t few_points = 16;
  };
  void init(PointSet& set, std::size_t count, double density, Rng& rng) const;

  Domain domain_;
  double delta_;
  PointSet pickups_;
  PointSet dropoffs_;
};

}  // namespace retreat::physics
