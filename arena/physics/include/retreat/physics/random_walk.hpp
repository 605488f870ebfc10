#pragma once
/// @file
/// The robots' ergodic random walk: run-and-tumble of the projected point with specular
/// reflection.
///
/// Why this walk. The model needs positions whose stationary density is uniform on D and
/// headings that are uniform, so that two robots meet with mean relative speed (4/π)v
/// (MODEL.md §2). The walk is defined on the projected point q = p + l·e(θ), which the
/// barrier-certificate map makes a fully actuated single integrator (any velocity of speed v is
/// reachable when v ≤ l·max_turn_rate, which WorldParams::validate() demands), so q can follow
/// the walk exactly:
///  - runs: q moves in a straight line at speed v;
///  - tumbles: at the events of a Poisson process of rate tumble_rate the direction is redrawn
///    uniformly (an exponentially distributed run time);
///  - reflection: when q comes within the walk inset of ∂D while moving outwards, the direction
///    is mirrored about the boundary normal (specular reflection).
/// Billiard flow with specular reflection preserves the Liouville measure (uniform position ×
/// uniform direction), and uniform tumbles preserve it as well, so the stationary density of q
/// is uniform on the walk region {signed_distance ≤ −walk_inset}. A diffuse (cosine-law)
/// reflection would also do; a uniform-direction reflection would not (it over-weights grazing
/// directions and piles robots up at the wall). The centre p = q − l·e trails q by l = 4 cm, so
/// its density equals q's away from the boundary and is smeared by at most l near it.
/// The walk reflects before the boundary barrier can act (walk_inset in params.hpp), so the
/// barrier never bends a lone robot's path.
///
/// Why runs are long (default mean run v/tumble_rate = 5 m at v = 0.1): the pick-up rate
/// Ω_p = 2δvλ_p counts fresh area swept by a 2δ-wide strip; after a tumble the new strip
/// overlaps the old one over a length of order δ, so runs comparable to 2δ re-sweep their own
/// path (measured: 0.5 m runs at δ = 0.11 cut the pick-up rate by 30 %).
///
/// Unblocking (bump and turn): barrier certificates stall two robots that meet nearly head-on
/// (the QP removes the whole approach component and leaves almost nothing). A walker whose
/// progress along its direction stays below v/2 for unblock_time re-orients uniformly, as a
/// tumble. Without it a stalled pair waits for a tumble (mean 1/tumble_rate), which makes the
/// contact duration τ_r a property of the tumble rate, and with tumble_rate = 0 the swarm jams.

#include "retreat/core/rng.hpp"
#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// The walk's state: the current direction of the projected point and the next tumble time.
struct WalkState {
  Vec2 direction = Vec2::UnitX();  ///< unit vector
  double next_tumble = 0.0;        ///< time of the next re-orientation [s]
  double blocked_since = -1.0;     ///< start of the current stall, −1 if progressing [s]
};

/// A walk starting at time @p now in direction @p direction (unit) with its first tumble after
/// an Exp(@p tumble_rate) run.
WalkState start_walk(const Vec2& direction, double now, double tumble_rate, Rng& rng);

/// Applies every tumble due at or before @p now (each draws a uniform direction and schedules
/// the next one an Exp(@p tumble_rate) later). Returns true if the direction changed.
bool apply_tumbles(WalkState& walk, double now, double tumble_rate, Rng& rng);

/// Records the barrier-filtered velocity @p u at time @p now: if its component along the
/// direction stays below @p speed / 2 for @p unblock_time, draws a uniform direction (the
/// tumble schedule is unchanged). Returns true if it re-oriented.
bool unblock_if_stalled(WalkState& walk, const Vec2& u, double speed, double now,
                        double unblock_time, Rng& rng);

/// How a retreating robot leaves D (arena.retreat_unblock): along the outward normal of its
/// nearest boundary point, or, once it has been held below v/2 along that for unblock_time, along
/// a fixed detour drawn uniformly within 90° of the normal where it stalled (and again if it
/// stalls on the detour). Any fixed direction leaves a bounded convex D; one with an outward
/// component does so near where the robot stands.
///
/// Why (docs/experiments.md, "Retreats that never end"): retreating robots that meet near the
/// boundary each want to move along their own outward normal, the ones ahead are in the way, and
/// the barrier certificates leave every one of them a feasible velocity of zero; nothing else in
/// the model moves them.
struct RetreatDetour {
  bool active = false;              ///< the robot follows `direction`, not the normal
  Vec2 direction = Vec2::UnitX();   ///< unit vector
  double blocked_since = -1.0;      ///< start of the current stall, −1 if progressing [s]
};

/// The unit direction a retreating robot wants to move its projected point in.
inline Vec2 retreat_direction(const RetreatDetour& detour, const Vec2& outward_normal) {
  return detour.active ? detour.direction : outward_normal;
}

/// Records the barrier-filtered velocity @p u at time @p now: if its component along
/// retreat_direction stays below @p speed / 2 for @p unblock_time, draws a detour uniformly within
/// 90° of @p outward_normal. Returns true if it drew one.
bool detour_if_stalled(RetreatDetour& detour, const Vec2& u, const Vec2& outward_normal,
                       double speed, double now, double unblock_time, Rng& rng);

/// Mirrors the direction about the unit @p outward_normal if it points outwards
/// (d ← d − 2(dᵀn)n). Returns true if it reflected.
bool reflect_if_outward(WalkState& walk, const Vec2& outward_normal);

}  // namespace retreat::physics
