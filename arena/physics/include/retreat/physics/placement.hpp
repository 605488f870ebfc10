#pragma once
/// @file
/// Where robots start: non-overlapping and uniform, and where they enter.

#include <vector>

#include "retreat/physics/domain.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/physics/unicycle.hpp"

namespace retreat::physics {

/// @p count poses by random sequential adsorption: each projected point is uniform on the walk
/// region {sd ≤ −walk_inset}, each heading uniform, and a candidate is rejected while its centre
/// is closer than @p min_separation to an accepted centre. Conditional on not overlapping the
/// positions are uniform. Precondition: count ≤ max_robots(params) (WorldParams::validate()),
/// which keeps the covered fraction ≤ 40 %, well below the 54.7 % jamming limit.
/// @throws std::logic_error if 10⁴ attempts per robot were not enough (an invariant violation).
std::vector<Pose> place_robots(const Domain& domain, std::size_t count, double walk_inset,
                               double projection_distance, double min_separation, Rng& rng);

}  // namespace retreat::physics
