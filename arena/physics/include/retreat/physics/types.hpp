#pragma once
/// @file
/// Small vocabulary types shared by every part of retreat::physics.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string_view>

namespace retreat::physics {

/// A point or a velocity in the plane [m] or [m/s].
using Vec2 = Eigen::Vector2d;

/// Robot identifier: 0, 1, 2, ... in the order robots are created (see World).
using RobotId = std::uint32_t;

/// "No robot": the partner of a robot-level contact record.
inline constexpr RobotId no_robot = std::numeric_limits<RobotId>::max();

/// Where a robot is in its life cycle. Same order as retreat::wire::Phase.
enum class Phase : std::uint8_t {
  waiting = 0,     ///< outside the domain, queued
  inside = 1,      ///< in the domain (including while driving in through the boundary)
  retreating = 2,  ///< told to retreat, driving out; still moves and still causes encounters
  departed = 3,    ///< has left the domain for good
};

/// Lower-case name of @p phase.
std::string_view to_string(Phase phase);

/// The CTMC state of a robot (MODEL.md §3): free, loaded, free-in-contact, loaded-in-contact.
/// "In contact" means some other robot is within 2δ.
enum class TaskState : std::uint8_t { f = 0, l = 1, fc = 2, lc = 3 };

/// Number of TaskState values.
inline constexpr std::size_t task_state_count = 4;

/// The state of a robot that is @p loaded and @p in_contact.
constexpr TaskState task_state(bool loaded, bool in_contact) noexcept {
  return static_cast<TaskState>((loaded ? 1 : 0) + (in_contact ? 2 : 0));
}

/// `f`, `l`, `fc` or `lc`.
std::string_view to_string(TaskState state);

}  // namespace retreat::physics
