#include "retreat/wire/messages.hpp"

namespace retreat::wire {

std::string_view to_string(Phase phase) {
  switch (phase) {
    case Phase::waiting: return "waiting";
    case Phase::inside: return "inside";
    case Phase::retreating: return "retreating";
    case Phase::departed: return "departed";
  }
  return "invalid";
}

std::string_view type_name(MessageKind kind) {
  switch (kind) {
    case MessageKind::proximity_frame: return "retreat::msg::ProximityFrame";
    case MessageKind::decision: return "retreat::msg::Decision";
    case MessageKind::agent_status: return "retreat::msg::AgentStatus";
    case MessageKind::arena_telemetry: return "retreat::msg::ArenaTelemetry";
    case MessageKind::poses: return "retreat::msg::Poses";
  }
  return "invalid";
}

}  // namespace retreat::wire
