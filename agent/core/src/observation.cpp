#include "retreat/agent/observation.hpp"

namespace retreat::agent {

std::string_view to_string(RobotPhase phase) {
  switch (phase) {
    case RobotPhase::waiting:
      return "waiting";
    case RobotPhase::inside:
      return "inside";
    case RobotPhase::retreating:
      return "retreating";
    case RobotPhase::departed:
      return "departed";
  }
  return "unknown";
}

}  // namespace retreat::agent
