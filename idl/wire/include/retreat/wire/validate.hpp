#pragma once
/// @file
/// Checks a received sample before it is passed on. Invalid samples are dropped and counted by
/// the transport layer (docs/protocol.md, "Validation").

#include <optional>
#include <string_view>

#include "retreat/wire/messages.hpp"

namespace retreat::wire {

/// Why a sample was rejected; `ok` when it was not.
enum class SampleFault {
  ok,
  wrong_robot,      ///< robot id does not match the per-robot topic it came on
  bad_time,         ///< time is NaN, infinite or negative
  bad_tick,         ///< tick is negative
  bad_phase,        ///< phase octet out of range
  bad_value,        ///< another field is out of range (NaN estimate, pose off the map...)
};
std::string_view to_string(SampleFault fault);

/// Validates a sample. `topic_robot` is the robot id of the per-robot topic the sample arrived
/// on, or nullopt for shared topics (then any robot id is allowed).
SampleFault validate(const AnyMessage& sample, std::optional<RobotId> topic_robot);

}  // namespace retreat::wire
