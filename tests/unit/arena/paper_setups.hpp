#pragma once
/// @file
/// World parameters of the paper's validation set-ups (MODEL.md §6), shared by the statistical
/// tests of retreat::physics.

#include <cmath>
#include <cstdint>

#include "retreat/physics/params.hpp"

namespace retreat::physics::testing {

/// Encounter-model validation (λ = 0.99, δ = 0.11, v = 1): @p robots robots in a square sized
/// for density @p lambda. The platform numbers are the Robotarium's scaled with v (every rate
/// ×10, every time ÷10 relative to v = 0.1), so the geometry of avoidance is the same as in the
/// default scenario: γ = 10⁵ (10⁴ at v = 0.1, see params.hpp), max_turn_rate = 1.25·v/l,
/// physics_dt = 0.01 s (1 cm per step), runs of 5 m (tumble_rate 0.2/s), unblock after 0.2 s ≈
/// 2δ/v, boundary_gain = 0.5/physics_dt.
inline WorldParams encounter_validation(std::uint32_t robots, double lambda, double v = 1.0) {
  WorldParams p;
  p.encounter_model = EncounterModel::physical;
  p.shape = DomainShape::rectangle;
  p.width = std::sqrt(robots / lambda);
  p.height = p.width;
  p.robots_inside = robots;
  p.robots_waiting = 0;
  p.lambda_in = 0.0;
  p.delta = 0.11;
  p.v = v;
  p.max_speed = v;
  p.projection_distance = 0.04;
  p.max_turn_rate = 1.25 * v / p.projection_distance;
  p.physics_dt = 0.01 / v;
  p.tick_dt = p.physics_dt;
  p.gamma = 1.0e5 * v;
  p.boundary_gain = 0.5 / p.physics_dt;
  p.tumble_rate = 0.2 * v;
  p.unblock_time = 0.2 / v;
  p.lambda_p = 0.82;
  p.lambda_d = 0.66;
  p.record_encounters = true;
  p.seed = 20190520;
  return p;
}

/// Throughput curve (v = 0.1, δ = 0.11, λ_p = 0.82, λ_d = 0.66): the same world as
/// encounter_validation() at v = 0.1, i.e. the v = 1 world with time stretched by 10
/// (physics_dt = 0.1 s still moves 1 cm per step).
inline WorldParams throughput_curve(std::uint32_t robots, double lambda) {
  WorldParams p = encounter_validation(robots, lambda, 0.1);
  p.record_encounters = false;
  return p;
}

/// 4δ(4/π)v [m²/s]: the swept-area coefficient c of MODEL.md §2.
inline double swept_area_rate(const WorldParams& p) {
  return 4.0 * p.delta * (4.0 / 3.14159265358979323846) * p.v;
}

}  // namespace retreat::physics::testing
