#pragma once
/// @file
/// The world's parameters: the `arena:` section of a scenario file, plus the few `model:`
/// numbers the physics needs (δ, v, λ_p, λ_d, ρ). The scenario loader fills both this struct and
/// retreat::model::ModelParams from the same file; the physics never depends on the model library.

#include <cstdint>
#include <string>
#include <string_view>

#include "retreat/core/enum_names.hpp"
#include "retreat/physics/domain.hpp"

namespace retreat::physics {

/// How encounters are produced (`arena.encounter_model`).
enum class EncounterModel {
  physical,  ///< unicycles, random walk, barrier certificates; encounters are geometric
  kinetic,   ///< no positions; encounters, contacts and task events are Poisson processes
};
constexpr EnumNames<EncounterModel, 2> enum_names(EncounterModel) {
  return {{{{EncounterModel::physical, "physical"}, {EncounterModel::kinetic, "kinetic"}}}};
}

/// Shape of the domain D (centred on the origin, axes aligned) (`arena.shape`).
enum class DomainShape { ellipse, rectangle };
constexpr EnumNames<DomainShape, 2> enum_names(DomainShape) {
  return {{{{DomainShape::ellipse, "ellipse"}, {DomainShape::rectangle, "rectangle"}}}};
}

/// What happens when the waiting robots have all entered (`arena.queue`).
enum class QueueKind {
  finite,   ///< robots_waiting robots, then no more
  endless,  ///< robots_waiting robots are always queued; each entry creates a new robot id
};
constexpr EnumNames<QueueKind, 2> enum_names(QueueKind) {
  return {{{{QueueKind::finite, "finite"}, {QueueKind::endless, "endless"}}}};
}

/// Arrival process of waiting robots (`arena.influx`).
enum class InfluxKind {
  steady,   ///< one arrival every 1/(λ_in·|D|) seconds
  poisson,  ///< Poisson arrivals at rate λ_in·|D|
};
constexpr EnumNames<InfluxKind, 2> enum_names(InfluxKind) {
  return {{{{InfluxKind::steady, "steady"}, {InfluxKind::poisson, "poisson"}}}};
}

/// Parameters of a world. Defaults: the paper's Robotarium experiment (MODEL.md §6) with the
/// Robotarium's platform numbers. Field names are the scenario keys: `arena.<field>` except the
/// five marked `model.<field>`.
///
/// Choosing γ. The cubic barrier starts to slow an approach where (γ/2)h³ ≈ 2·d·v, so the
/// distance at which robots begin to avoid each other grows as γ/v shrinks. The encounter model
/// (Ω_c = 4δ(4/π)vλ) assumes robots pass within 2δ as if they did not avoid each other, so the
/// barrier must act inside 2δ: γ ≳ 10⁵·v (per m/s). Measured onset rate / Ω_c at the
/// Robotarium experiment's numbers (δ = 0.1, v = 0.1, D_s = 0.13, l = 0.04, λ = 1.5): γ = 100:
/// 0 (no robot ever comes within 2δ, so every λ̂ would be 0), 10³: 0.49, 3·10³: 0.83,
/// 10⁴: 0.99. Hence the default 10⁴ (the Robotarium MATLAB simulator's value), not the Python
/// simulator's 100. Scale γ with v (10⁵ at v = 1) to keep the same geometry.
struct WorldParams {
  // --- arena: what is simulated ---------------------------------------------------------------
  EncounterModel encounter_model = EncounterModel::physical;
  DomainShape shape = DomainShape::ellipse;
  double semi_axis_x = 1.2;                  ///< ellipse semi-axis along x [m]
  double semi_axis_y = 0.8;                  ///< ellipse semi-axis along y [m]
  double width = 3.2;                        ///< rectangle extent along x [m]
  double height = 2.0;                       ///< rectangle extent along y [m]
  std::uint32_t robots_inside = 8;           ///< robots in D at t = 0 (ids 0 .. robots_inside-1)
  std::uint32_t robots_waiting = 4;          ///< robots queued outside at t = 0 (the next ids)
  QueueKind queue = QueueKind::finite;
  InfluxKind influx = InfluxKind::steady;
  double lambda_in = 0.02;  ///< λ_in: influx [robots/(m²·s)]; arrivals λ_in·|D| per s

  // --- arena: time ------------------------------------------------------------------------------
  double physics_dt = 0.01;  ///< integration step [s]
  double tick_dt = 0.03;     ///< the agents' dt, one frame per tick [s]; a multiple of physics_dt

  // --- arena: robots and barrier certificates --------------------------------------------------
  double robot_radius = 0.055;  ///< footprint radius r [m]
  double max_speed = 0.2;       ///< |linear speed| limit [m/s]
  double max_turn_rate = 3.6;   ///< |turn rate| limit [rad/s]
  double gamma = 1.0e4;  ///< barrier gain γ in −2(x_i−x_j)ᵀu_i ≤ (γ/2)h³ [1/(m⁴·s)]
  double safety_distance = 0.13;      ///< D_s: robot centres never come closer [m]
  double projection_distance = 0.04;  ///< l: the controlled point is l ahead of the centre [m]
  double boundary_gain = 30.0;        ///< α in the boundary barrier nᵀu ≤ α·clearance [1/s]
  double tumble_rate = 0.02;          ///< random-walk re-orientation rate [1/s] (runs ≫ 2δ)
  double unblock_time = 2.0;       ///< a walker held below v/2 this long re-orients [s] (≈ 2δ/v)
  /// An option beside the reference, off in every shipped scenario: a retreating robot held below
  /// v/2 for unblock_time leaves along a random direction within 90° of its outward normal
  /// instead (random_walk.hpp, RetreatDetour). Off (the reference): it drives along the outward
  /// normal of its nearest boundary point until it is out.
  bool retreat_unblock = false;
  bool record_encounters = false;  ///< keep per-pair and per-robot contact intervals
  double missed_onsets = 0.0;  ///< each robot's sensor misses each encounter onset with this chance [-]
  double false_onsets = 0.0;   ///< each robot's sensor reports spurious onsets at this rate inside D [1/s]

  // --- arena: external (real) robots in a mixed swarm -----------------------------------------
  /// Robots 0 .. external_robots−1 are real: their poses come from outside (set_external_pose),
  /// not from the simulation; simulated robots avoid them and meet them. Physical world only.
  std::uint32_t external_robots = 0;
  double external_frozen_after = 0.5;  ///< a pose older than this [s of arena time] is frozen
  double external_lost_after = 5.0;    ///< ... and older than this, the robot is lost [s]
  double external_max_speed = 1.0;     ///< a pose implying a faster move is a jump: dropped [m/s]
  std::uint64_t seed = 1;          ///< scenario seed; every random stream derives from it

  // --- model: the paper's numbers the physics needs ---------------------------------------------
  double v = 0.1;          ///< `model.v`: speed of the random walk [m/s]
  double delta = 0.1;      ///< `model.delta`: δ; contact within 2δ, pick-up within δ [m]
  double lambda_p = 1.32;  ///< `model.lambda_p`: pick-up location density [1/m²]
  double lambda_d = 1.32;  ///< `model.lambda_d`: drop-off location density [1/m²]
  double rho = 2.44;       ///< `model.rho`: contact resolution rate, kinetic world only [1/s]

  /// Checks every field and the cross-field conditions: r < δ, 2r ≤ D_s, v ≤ max_speed,
  /// l < r + δ, physics_dt ≤ tick_dt in a whole number of steps, the walk region is not empty,
  /// robots_inside (and, with a finite queue, robots_inside + robots_waiting) ≤ max_robots(),
  /// an endless queue shows ≥ 1 robot, and the limits below (max_extent, max_start_robots,
  /// max_substeps_per_tick, max_events_per_tick, max_arrivals_per_tick; max_task_locations in the
/// physical world).
  /// Physical world only: D_s < 2δ (or no encounter can begin), v ≤ l·max_turn_rate (the walk
  /// needs q fully actuated at speed v),
  /// max_speed·physics_dt ≤ δ/4, max_turn_rate·physics_dt ≤ 0.5, boundary_gain·physics_dt ≤ 1.
  /// Kinetic world only: ρ > 0. Sensing noise (both worlds): missed_onsets in [0, 1],
  /// false_onsets finite and >= 0. External robots: physical world only, at most robots_inside,
  /// 0 < external_frozen_after <= external_lost_after, external_max_speed > 0.
  /// @throws std::invalid_argument with one line naming the first bad key, its value and the
  ///         allowed range, e.g. `arena.physics_dt = 0.007: must divide agent.dt (0.03 s) into
  ///         a whole number of steps`.
  void validate() const;

  /// Visits the `arena.*` keys in scenario-file order (the Drake `Serialize()` idiom): the
  /// archive is called as `a(name, member)`. The copies of `model.*` and `agent.*` values and
  /// the seed are not keys: the scenario's resolve() fills them.
  template <class Archive>
  void serialize(Archive& a) {
    a("encounter_model", encounter_model);
    a("shape", shape);
    a("semi_axis_x", semi_axis_x);
    a("semi_axis_y", semi_axis_y);
    a("width", width);
    a("height", height);
    a("robots_inside", robots_inside);
    a("robots_waiting", robots_waiting);
    a("queue", queue);
    a("influx", influx);
    a("physics_dt", physics_dt);
    a("robot_radius", robot_radius);
    a("max_speed", max_speed);
    a("max_turn_rate", max_turn_rate);
    a("gamma", gamma);
    a("safety_distance", safety_distance);
    a("projection_distance", projection_distance);
    a("boundary_gain", boundary_gain);
    a("tumble_rate", tumble_rate);
    a("unblock_time", unblock_time);
    a("retreat_unblock", retreat_unblock);
    a("record_encounters", record_encounters);
    a("missed_onsets", missed_onsets);
    a("false_onsets", false_onsets);
    a("external_robots", external_robots);
    a("external_frozen_after", external_frozen_after);
    a("external_lost_after", external_lost_after);
    a("external_max_speed", external_max_speed);
  }
};

/// Limits that keep what a world allocates at its start, and the work of one tick, bounded
/// whatever a scenario asks for (validate() checks them; each is far above any swarm the
/// framework was measured with: 10⁵ robots, docs/benchmarks.md).
/// Semi-axes, width and height [m]: beyond this a double is too coarse for a physics step's
/// motion near the boundary (2 mm at 0.2 m/s, against an ulp of 1.2e-10 m at 10⁶ m).
inline constexpr double max_extent = 1e6;
/// robots_inside + robots_waiting: every one of them (and its agent) exists from the start.
inline constexpr std::uint32_t max_start_robots = 1'000'000;
/// round(λ_p·|D|) pick-up and round(λ_d·|D|) drop-off locations, each (physical world).
inline constexpr double max_task_locations = 1e6;
/// Physics steps in one tick, round(tick_dt / physics_dt).
inline constexpr double max_substeps_per_tick = 1e6;
/// Expected events of one robot in one tick that the world draws one by one: tumbles
/// (tumble_rate·tick_dt, physical world), pick-ups and drop-offs (2δvλ_p·tick_dt and
/// 2δvλ_d·tick_dt, kinetic world).
inline constexpr double max_events_per_tick = 1e3;
/// Expected arrivals in one tick, λ_in·|D|·tick_dt: the influx draws them one by one, with a
/// finite queue too (the scenario bounds an endless queue's arrivals over the whole run as well).
inline constexpr double max_arrivals_per_tick = 1e5;

/// Maximal robot count a world accepts: the robots' safety discs (diameter D_s) may cover at most
/// 40 % of the walkable area (D shrunk by r + l). Random sequential placement reaches 40 %
/// quickly; its jamming limit is 54.7 %. Saturates at the largest std::uint32_t.
std::uint32_t max_robots(const WorldParams& params);

/// D: the ellipse or rectangle @p params describes.
Domain domain_of(const WorldParams& params);

/// Physics substeps per tick, round(tick_dt / physics_dt). Precondition: validate() passed.
std::int64_t substeps_per_tick(const WorldParams& params);

/// Distance inside the boundary of D beyond which the walk reflects its projected point:
/// r + l + v·(2·physics_dt + 1/boundary_gain) [m] (see random_walk.hpp).
double walk_inset(const WorldParams& params);

}  // namespace retreat::physics
