#pragma once
/// @file
/// Plain C++ mirrors of the IDL types in idl/msg/retreat_msgs.idl. Everything outside the vendor
/// adapters speaks these; the adapters translate to and from the generated types.

#include <cstdint>
#include <string_view>
#include <variant>
#include <vector>

namespace retreat::wire {

using RobotId = std::uint32_t;

/// Robot phase as carried on the wire (an octet).
enum class Phase : std::uint8_t { waiting = 0, inside = 1, retreating = 2, departed = 3 };
inline constexpr std::uint8_t phase_count = 4;
std::string_view to_string(Phase phase);

/// arena or robot driver -> agent, on `<prefix>/robot_<id>/proximity`.
struct ProximityFrame {
  RobotId robot_id = 0;
  std::int64_t tick = 0;      ///< arena tick this frame describes (>= 0, increasing)
  double time = 0.0;          ///< arena clock at that tick [s] (>= 0, non-decreasing)
  Phase phase = Phase::waiting;
  bool in_contact = false;    ///< any robot within 2δ now
  std::uint32_t new_onsets = 0;  ///< encounters that began since the previous frame
  bool operator==(const ProximityFrame&) const = default;
};

/// agent -> arena or robot driver, on `<prefix>/robot_<id>/decision`.
struct Decision {
  RobotId robot_id = 0;
  std::int64_t tick = 0;  ///< the frame tick this decision answers
  double time = 0.0;      ///< that frame's time [s]
  bool retreat = false;   ///< leave the domain now (sticky once true)
  bool operator==(const Decision&) const = default;
};

/// agent -> observers, on `<prefix>/agent_status` (keyed by robot id).
struct AgentStatus {
  RobotId robot_id = 0;
  std::int64_t tick = 0;
  double time = 0.0;
  bool deciding = false;    ///< inside for at least L and not retreating
  bool retreating = false;  ///< has decided to retreat
  std::uint32_t onsets_in_window = 0;  ///< y_iL(t)
  double lambda_hat = 0.0;  ///< density estimate λ̂ [robots/m²]
  double epsilon = 0.0;     ///< controller rate ε(λ̂) [1/s]
  std::uint64_t frames_dropped = 0;
  bool operator==(const AgentStatus&) const = default;
};

/// arena -> observers, on `<prefix>/arena_telemetry` (keyed by arena id).
struct ArenaTelemetry {
  std::uint32_t arena_id = 0;
  std::int64_t tick = 0;
  double time = 0.0;
  std::uint32_t inside = 0;
  std::uint32_t waiting = 0;
  std::uint32_t retreating = 0;
  std::uint32_t departed = 0;
  std::uint32_t lost_agents = 0;
  double true_density = 0.0;  ///< robots inside / |D| [robots/m²]
  std::uint64_t deliveries = 0;
  double ticks_per_second = 0.0;
  bool operator==(const ArenaTelemetry&) const = default;
};

struct RobotPose {
  RobotId robot_id = 0;
  float x = 0.0f;      ///< [m]
  float y = 0.0f;      ///< [m]
  float theta = 0.0f;  ///< heading [rad]
  Phase phase = Phase::waiting;
  bool loaded = false;
  bool operator==(const RobotPose&) const = default;
};

struct Point2 {
  float x = 0.0f;
  float y = 0.0f;
  bool operator==(const Point2&) const = default;
};

/// arena -> observers, on `<prefix>/poses` (keyed by arena id). Display only: never read by agents.
struct Poses {
  std::uint32_t arena_id = 0;
  std::int64_t tick = 0;
  double time = 0.0;
  std::vector<RobotPose> robots;
  std::vector<Point2> pickups;
  std::vector<Point2> dropoffs;
  bool operator==(const Poses&) const = default;
};

/// Every message kind of the contract, in IDL order.
enum class MessageKind { proximity_frame, decision, agent_status, arena_telemetry, poses };
using AnyMessage = std::variant<ProximityFrame, Decision, AgentStatus, ArenaTelemetry, Poses>;

template <class M> struct KindOf;
template <> struct KindOf<ProximityFrame> { static constexpr MessageKind value = MessageKind::proximity_frame; };
template <> struct KindOf<Decision> { static constexpr MessageKind value = MessageKind::decision; };
template <> struct KindOf<AgentStatus> { static constexpr MessageKind value = MessageKind::agent_status; };
template <> struct KindOf<ArenaTelemetry> { static constexpr MessageKind value = MessageKind::arena_telemetry; };
template <> struct KindOf<Poses> { static constexpr MessageKind value = MessageKind::poses; };

/// The IDL type name, identical for both vendors (e.g. "retreat::msg::ProximityFrame").
std::string_view type_name(MessageKind kind);

}  // namespace retreat::wire
