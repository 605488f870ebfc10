#pragma once
/// @file
/// The world the arena program runs: one interface, two implementations (physical: unicycles
/// with barrier certificates; kinetic: Poisson encounters, no positions), made by make_world().
///
/// Robot ids. Finite queue: 0 .. robots_inside−1 start inside, robots_inside ..
/// robots_inside+robots_waiting−1 wait, in entry order. Endless queue: the same at t = 0, and
/// whenever a waiting robot enters, a new robot with the next unused id joins the back of the
/// queue, so robots_waiting robots are always waiting and ids only grow.
///
/// Time. step_tick() advances tick_dt = substeps_per_tick physics steps. Frames describe the
/// world at the end of the tick. A retreat command takes effect at once (the next step drives
/// out). Everything is deterministic for a given WorldParams (seed included) and command order.

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "retreat/physics/encounter_tracker.hpp"
#include "retreat/physics/params.hpp"
#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// What one robot's agent receives each tick (mirrors retreat::wire::ProximityFrame).
struct RobotFrame {
  RobotId id = 0;
  std::int64_t tick = 0;  ///< tick this frame describes (0 before the first step)
  double time = 0.0;      ///< tick·tick_dt [s]
  Phase phase = Phase::waiting;
  bool in_contact = false;       ///< some robot within 2δ now
  std::uint32_t new_onsets = 0;  ///< encounter onsets since the previous frame
};

/// The verdict on a retreat command.
enum class CommandVerdict : std::uint8_t {
  accepted,            ///< the robot was inside and now retreats
  already_retreating,  ///< repeated command (decisions are sticky); no effect
  not_inside,          ///< the robot is waiting or has departed: rejected
  unknown_robot,       ///< no robot has this id: rejected
};

/// Counters of retreat commands by verdict.
struct CommandCounts {
  std::uint64_t accepted = 0;
  std::uint64_t already_retreating = 0;
  std::uint64_t rejected_not_inside = 0;
  std::uint64_t rejected_unknown = 0;
};

/// Ground truth of the whole world at the end of a tick.
struct Telemetry {
  std::int64_t tick = 0;
  double time = 0.0;          ///< [s]
  std::uint32_t inside = 0;   ///< phase inside (entering robots included)
  std::uint32_t waiting = 0;  ///< queued (endless queue: the robots_waiting materialised ones)
  std::uint32_t retreating = 0;
  std::uint32_t departed = 0;
  double true_density = 0.0;  ///< robots in D (inside + retreating) / |D| [robots/m²]
  std::uint64_t deliveries = 0;
  std::uint64_t onsets = 0;  ///< all encounter onsets so far (each robot of a pair counts one)
  std::array<std::uint32_t, task_state_count> state_counts{};  ///< inside robots now in f,l,fc,lc
  std::array<double, task_state_count> state_time{};  ///< inside-robot time in f,l,fc,lc [s]
  CommandCounts commands;
  std::uint64_t qp_relaxed = 0;  ///< robot-steps whose barrier QP had to be relaxed (physical)
};

/// Cumulative statistics of one robot.
struct RobotStats {
  Phase phase = Phase::waiting;
  double entered_at = -1.0;   ///< time it was in D first (0 for robots inside at start, −1 if it
                              ///< has not entered) [s]
  double departed_at = -1.0;  ///< time it left D (−1 if it has not) [s]
  std::uint64_t onsets = 0;
  std::uint64_t pickups = 0;
  std::uint64_t deliveries = 0;
  std::array<double, task_state_count> state_time{};  ///< time inside in f,l,fc,lc [s]
  bool loaded = false;
};

/// One robot in poses() (display only; never given to agents).
struct RobotPose {
  RobotId id = 0;
  double x = 0.0;      ///< [m]
  double y = 0.0;      ///< [m]
  double theta = 0.0;  ///< [rad]
  Phase phase = Phase::inside;
  bool entering = false;  ///< still driving in through ∂D (its footprint may be outside D)
  bool loaded = false;
  bool in_contact = false;
};

/// Positions for display (physical world only).
struct Poses {
  std::int64_t tick = 0;
  double time = 0.0;
  std::vector<RobotPose> robots;  ///< robots in D (inside and retreating), ascending id
  std::vector<Vec2> pickups;
  std::vector<Vec2> dropoffs;
};

/// A simulated world. Not thread-safe; one owner calls everything.
class World {
 public:
  virtual ~World() = default;

  /// Tells robot @p id to retreat: it drives out through the nearest part of ∂D (kinetic: it
  /// leaves after a fixed drive-out time) and then departs. Counted by verdict in telemetry().
  virtual CommandVerdict command_retreat(RobotId id) = 0;

  /// Advances one tick (tick_dt seconds).
  virtual void step_tick() = 0;

  /// Mixed swarm (`arena.external_robots`): real robot @p id is at @p x, @p y [m] heading
  /// @p theta [rad], as measured outside (tracking or the robot's own estimate). The simulation
  /// never moves it: it stays at the last pose set (frozen) until the next. Simulated robots
  /// avoid it with their barrier certificates and meet it (onsets for both). A real robot whose
  /// footprint is wholly outside D departs, told to retreat or not: it leaves by its own motion.
  /// Returns false, changing nothing, when @p id is not a real robot in D. Physical world only
  /// (the kinetic world has no positions and returns false).
  virtual bool set_external_pose(RobotId id, double x, double y, double theta) {
    (void)id, (void)x, (void)y, (void)theta;
    return false;
  }

  /// Real robot @p id is lost (no pose for too long): it departs now, ending its contacts.
  /// Returns false when @p id is not a real robot in D.
  virtual bool lose_external(RobotId id) {
    (void)id;
    return false;
  }

  /// One frame per robot that is waiting, inside or retreating, plus one for each robot that
  /// departed during the last tick (phase departed, so its agent learns it), ascending id.
  virtual const std::vector<RobotFrame>& frames() const = 0;

  /// Ground truth at the end of the last tick.
  virtual Telemetry telemetry() const = 0;

  /// Positions and locations (physical); an empty Poses with tick and time set (kinetic).
  virtual Poses poses() const = 0;

  /// Statistics of robot @p id. @throws std::out_of_range for an unknown id.
  virtual const RobotStats& robot_stats(RobotId id) const = 0;

  /// Number of robot ids created so far (valid ids are 0 .. robot_count()−1).
  virtual std::size_t robot_count() const = 0;

  /// Contact intervals completed since the previous call (empty unless record_encounters).
  virtual std::vector<ContactRecord> take_contact_records() = 0;

  /// The validated parameters the world was made with.
  virtual const WorldParams& params() const = 0;
};

/// Validates @p params (throws std::invalid_argument like WorldParams::validate()) and makes
/// the world its encounter_model names.
std::unique_ptr<World> make_world(const WorldParams& params);

}  // namespace retreat::physics
