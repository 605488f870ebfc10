#include "fastdds_convert.hpp"

namespace retreat::transport::fastdds {

msg::ProximityFrame to_vendor(const wire::ProximityFrame& m) {
  msg::ProximityFrame v;
  v.robot_id(m.robot_id);
  v.tick(m.tick);
  v.time(m.time);
  v.phase(static_cast<uint8_t>(m.phase));
  v.in_contact(m.in_contact);
  v.new_onsets(m.new_onsets);
  return v;
}

wire::ProximityFrame to_plain(const msg::ProximityFrame& v) {
  return {v.robot_id(), v.tick(), v.time(), static_cast<wire::Phase>(v.phase()), v.in_contact(),
          v.new_onsets()};
}

msg::Decision to_vendor(const wire::Decision& m) {
  msg::Decision v;
  v.robot_id(m.robot_id);
  v.tick(m.tick);
  v.time(m.time);
  v.retreat(m.retreat);
  return v;
}

wire::Decision to_plain(const msg::Decision& v) {
  return {v.robot_id(), v.tick(), v.time(), v.retreat()};
}

msg::AgentStatus to_vendor(const wire::AgentStatus& m) {
  msg::AgentStatus v;
  v.robot_id(m.robot_id);
  v.tick(m.tick);
  v.time(m.time);
  v.deciding(m.deciding);
  v.retreating(m.retreating);
  v.onsets_in_window(m.onsets_in_window);
  v.lambda_hat(m.lambda_hat);
  v.epsilon(m.epsilon);
  v.frames_dropped(m.frames_dropped);
  return v;
}

wire::AgentStatus to_plain(const msg::AgentStatus& v) {
  return {v.robot_id(),         v.tick(),       v.time(),    v.deciding(),      v.retreating(),
          v.onsets_in_window(), v.lambda_hat(), v.epsilon(), v.frames_dropped()};
}

msg::ArenaTelemetry to_vendor(const wire::ArenaTelemetry& m) {
  msg::ArenaTelemetry v;
  v.arena_id(m.arena_id);
  v.tick(m.tick);
  v.time(m.time);
  v.inside(m.inside);
  v.waiting(m.waiting);
  v.retreating(m.retreating);
  v.departed(m.departed);
  v.lost_agents(m.lost_agents);
  v.true_density(m.true_density);
  v.deliveries(m.deliveries);
  v.ticks_per_second(m.ticks_per_second);
  return v;
}

wire::ArenaTelemetry to_plain(const msg::ArenaTelemetry& v) {
  return {v.arena_id(),    v.tick(),        v.time(),         v.inside(),
          v.waiting(),     v.retreating(),  v.departed(),     v.lost_agents(),
          v.true_density(), v.deliveries(), v.ticks_per_second()};
}

msg::Poses to_vendor(const wire::Poses& m) {
  msg::Poses v;
  v.arena_id(m.arena_id);
  v.tick(m.tick);
  v.time(m.time);
  v.robots().reserve(m.robots.size());
  for (const auto& r : m.robots) {
    msg::RobotPose p;
    p.robot_id(r.robot_id);
    p.x(r.x);
    p.y(r.y);
    p.theta(r.theta);
    p.phase(static_cast<uint8_t>(r.phase));
    p.loaded(r.loaded);
    v.robots().push_back(p);
  }
  for (const auto& q : m.pickups) {
    msg::Point2 p;
    p.x(q.x);
    p.y(q.y);
    v.pickups().push_back(p);
  }
  for (const auto& q : m.dropoffs) {
    msg::Point2 p;
    p.x(q.x);
    p.y(q.y);
    v.dropoffs().push_back(p);
  }
  return v;
}

wire::Poses to_plain(const msg::Poses& v) {
  wire::Poses m;
  m.arena_id = v.arena_id();
  m.tick = v.tick();
  m.time = v.time();
  m.robots.reserve(v.robots().size());
  for (const auto& p : v.robots()) {
    m.robots.push_back(
        {p.robot_id(), p.x(), p.y(), p.theta(), static_cast<wire::Phase>(p.phase()), p.loaded()});
  }
  for (const auto& p : v.pickups()) m.pickups.push_back({p.x(), p.y()});
  for (const auto& p : v.dropoffs()) m.dropoffs.push_back({p.x(), p.y()});
  return m;
}

}  // namespace retreat::transport::fastdds
