#include "retreat/wire/validate.hpp"

#include <cmath>
#include <type_traits>

namespace retreat::wire {
namespace {

bool valid_time(double t) { return std::isfinite(t) && t >= 0.0; }
bool valid_phase(Phase p) { return static_cast<std::uint8_t>(p) < phase_count; }

SampleFault check_robot(RobotId robot, std::optional<RobotId> topic_robot) {
  return topic_robot && *topic_robot != robot ? SampleFault::wrong_robot : SampleFault::ok;
}

SampleFault check_clock(std::int64_t tick, double time) {
  if (tick < 0) return SampleFault::bad_tick;
  if (!valid_time(time)) return SampleFault::bad_time;
  return SampleFault::ok;
}

SampleFault check(const ProximityFrame& m, std::optional<RobotId> topic_robot) {
  if (auto f = check_robot(m.robot_id, topic_robot); f != SampleFault::ok) return f;
  if (auto f = check_clock(m.tick, m.time); f != SampleFault::ok) return f;
  return valid_phase(m.phase) ? SampleFault::ok : SampleFault::bad_phase;
}

SampleFault check(const Decision& m, std::optional<RobotId> topic_robot) {
  if (auto f = check_robot(m.robot_id, topic_robot); f != SampleFault::ok) return f;
  return check_clock(m.tick, m.time);
}

SampleFault check(const AgentStatus& m, std::optional<RobotId> topic_robot) {
  if (auto f = check_robot(m.robot_id, topic_robot); f != SampleFault::ok) return f;
  if (auto f = check_clock(m.tick, m.time); f != SampleFault::ok) return f;
  const bool finite = std::isfinite(m.lambda_hat) && std::isfinite(m.epsilon);
  return finite && m.lambda_hat >= 0.0 && m.epsilon >= 0.0 ? SampleFault::ok
                                                           : SampleFault::bad_value;
}

SampleFault check(const ArenaTelemetry& m, std::optional<RobotId>) {
  if (auto f = check_clock(m.tick, m.time); f != SampleFault::ok) return f;
  const bool ok = std::isfinite(m.true_density) && m.true_density >= 0.0 &&
                  std::isfinite(m.ticks_per_second) && m.ticks_per_second >= 0.0;
  return ok ? SampleFault::ok : SampleFault::bad_value;
}

SampleFault check(const Poses& m, std::optional<RobotId> topic_robot) {
  // On a per-robot topic (a real robot's tracked pose) the sample is about that robot only.
  if (auto f = check_robot(m.arena_id, topic_robot); f != SampleFault::ok) return f;
  if (topic_robot && (m.robots.size() != 1 || m.robots[0].robot_id != *topic_robot)) {
    return SampleFault::wrong_robot;
  }
  if (auto f = check_clock(m.tick, m.time); f != SampleFault::ok) return f;
  for (const auto& r : m.robots) {
    if (!valid_phase(r.phase)) return SampleFault::bad_phase;
    if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.theta)) {
      return SampleFault::bad_value;
    }
  }
  for (const auto* points : {&m.pickups, &m.dropoffs}) {
    for (const auto& p : *points) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) return SampleFault::bad_value;
    }
  }
  return SampleFault::ok;
}

}  // namespace

std::string_view to_string(SampleFault fault) {
  switch (fault) {
    case SampleFault::ok: return "ok";
    case SampleFault::wrong_robot: return "wrong_robot";
    case SampleFault::bad_time: return "bad_time";
    case SampleFault::bad_tick: return "bad_tick";
    case SampleFault::bad_phase: return "bad_phase";
    case SampleFault::bad_value: return "bad_value";
  }
  return "invalid";
}

SampleFault validate(const AnyMessage& sample, std::optional<RobotId> topic_robot) {
  return std::visit([&](const auto& m) { return check(m, topic_robot); }, sample);
}

}  // namespace retreat::wire
