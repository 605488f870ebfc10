#include "cyclonedds_convert.hpp"

namespace retreat::transport::cyclonedds {

void to_vendor(const wire::ProximityFrame& in, retreat_msg_ProximityFrame& out) {
  out.robot_id = in.robot_id;
  out.tick = in.tick;
  out.time = in.time;
  out.phase = static_cast<uint8_t>(in.phase);
  out.in_contact = in.in_contact;
  out.new_onsets = in.new_onsets;
}

wire::ProximityFrame to_plain(const retreat_msg_ProximityFrame& m) {
  return {m.robot_id, m.tick, m.time, static_cast<wire::Phase>(m.phase), m.in_contact, m.new_onsets};
}

void to_vendor(const wire::Decision& in, retreat_msg_Decision& out) {
  out.robot_id = in.robot_id;
  out.tick = in.tick;
  out.time = in.time;
  out.retreat = in.retreat;
}

wire::Decision to_plain(const retreat_msg_Decision& m) {
  return {m.robot_id, m.tick, m.time, m.retreat};
}

void to_vendor(const wire::AgentStatus& in, retreat_msg_AgentStatus& out) {
  out.robot_id = in.robot_id;
  out.tick = in.tick;
  out.time = in.time;
  out.deciding = in.deciding;
  out.retreating = in.retreating;
  out.onsets_in_window = in.onsets_in_window;
  out.lambda_hat = in.lambda_hat;
  out.epsilon = in.epsilon;
  out.frames_dropped = in.frames_dropped;
}

wire::AgentStatus to_plain(const retreat_msg_AgentStatus& m) {
  return {m.robot_id,         m.tick,       m.time,    m.deciding,      m.retreating,
          m.onsets_in_window, m.lambda_hat, m.epsilon, m.frames_dropped};
}

void to_vendor(const wire::ArenaTelemetry& in, retreat_msg_ArenaTelemetry& out) {
  out.arena_id = in.arena_id;
  out.tick = in.tick;
  out.time = in.time;
  out.inside = in.inside;
  out.waiting = in.waiting;
  out.retreating = in.retreating;
  out.departed = in.departed;
  out.lost_agents = in.lost_agents;
  out.true_density = in.true_density;
  out.deliveries = in.deliveries;
  out.ticks_per_second = in.ticks_per_second;
}

wire::ArenaTelemetry to_plain(const retreat_msg_ArenaTelemetry& m) {
  return {m.arena_id, m.tick,       m.time,        m.inside,     m.waiting,         m.retreating,
          m.departed, m.lost_agents, m.true_density, m.deliveries, m.ticks_per_second};
}

namespace {
template <class Seq, class T>
void borrow(Seq& seq, std::vector<T>& items) {
  seq._maximum = static_cast<uint32_t>(items.size());
  seq._length = static_cast<uint32_t>(items.size());
  seq._buffer = items.empty() ? nullptr : items.data();
  seq._release = false;
}
}  // namespace

void to_vendor(const wire::Poses& in, retreat_msg_Poses& out, PosesScratch& scratch) {
  out.arena_id = in.arena_id;
  out.tick = in.tick;
  out.time = in.time;
  scratch.robots.clear();
  for (const auto& r : in.robots) {
    scratch.robots.push_back({r.robot_id, r.x, r.y, r.theta, static_cast<uint8_t>(r.phase), r.loaded});
  }
  scratch.pickups.clear();
  for (const auto& p : in.pickups) scratch.pickups.push_back({p.x, p.y});
  scratch.dropoffs.clear();
  for (const auto& p : in.dropoffs) scratch.dropoffs.push_back({p.x, p.y});
  borrow(out.robots, scratch.robots);
  borrow(out.pickups, scratch.pickups);
  borrow(out.dropoffs, scratch.dropoffs);
}

wire::Poses to_plain(const retreat_msg_Poses& m) {
  wire::Poses out;
  out.arena_id = m.arena_id;
  out.tick = m.tick;
  out.time = m.time;
  out.robots.reserve(m.robots._length);
  for (uint32_t i = 0; i < m.robots._length; ++i) {
    const auto& r = m.robots._buffer[i];
    out.robots.push_back({r.robot_id, r.x, r.y, r.theta, static_cast<wire::Phase>(r.phase), r.loaded});
  }
  for (uint32_t i = 0; i < m.pickups._length; ++i) {
    out.pickups.push_back({m.pickups._buffer[i].x, m.pickups._buffer[i].y});
  }
  for (uint32_t i = 0; i < m.dropoffs._length; ++i) {
    out.dropoffs.push_back({m.dropoffs._buffer[i].x, m.dropoffs._buffer[i].y});
  }
  return out;
}

}  // namespace retreat::transport::cyclonedds
