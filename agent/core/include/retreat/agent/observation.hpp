#pragma once
/// @file
/// What one robot observes about itself in one frame: the agent's only input. Not a wire type;
/// the program translates the transport's proximity frames into this.

#include <cstdint>
#include <string_view>

namespace retreat::agent {

/// Where the robot is in its life cycle, as reported by the arena or the robot's driver.
enum class RobotPhase : std::uint8_t {
  waiting,     ///< outside the domain, not yet entered
  inside,      ///< in the domain D, working and counting encounters
  retreating,  ///< driving out after a retreat decision; no longer decides
  departed,    ///< left the domain
};

/// Lower-case name of @p phase (`waiting`, `inside`, `retreating`, `departed`).
std::string_view to_string(RobotPhase phase);

/// One frame of the robot's own observation.
struct Observation {
  std::int64_t tick = 0;  ///< frame counter of the producer; increases by >= 1 per frame
  double time = 0.0;      ///< robot's own clock at this frame [s]; finite, >= 0, non-decreasing
  RobotPhase phase = RobotPhase::waiting;  ///< the robot's phase at this frame
  bool in_contact =
      false;  ///< any robot within 2δ now (informational; the algorithm counts onsets)
  std::uint32_t new_onsets = 0;  ///< encounter onsets since the previous frame, placed at `time`
  std::uint32_t robot_id = 0;    ///< the robot this frame describes
};

}  // namespace retreat::agent
