#include "world_base.hpp"

#include <stdexcept>
#include <string>

#include "retreat/core/seed.hpp"

namespace retreat::physics::detail {

WorldBase::WorldBase(const WorldParams& params)
    : params_(params),
      domain_(domain_of(params)),
      world_rng_(retreat::seed_for(params.seed, -1, retreat::Stream::world)),
      influx_(params.influx, params.lambda_in * domain_.area(), world_rng_),
      queue_kind_(params.queue) {}

void WorldBase::init_population() {
  for (std::uint32_t i = 0; i < params_.robots_inside; ++i) {
    RobotStats& stats = stats_[create_robot()];
    stats.phase = Phase::inside;
    stats.entered_at = 0.0;
  }
  for (std::uint32_t i = 0; i < params_.robots_waiting; ++i) {
    queue_.push_back(create_robot());
  }
}

RobotId WorldBase::create_robot() {
  const auto id = static_cast<RobotId>(stats_.size());
  stats_.emplace_back();
  in_contact_.push_back(0);
  onsets_since_frame_.push_back(0);
  departed_this_tick_.push_back(0);
  on_robot_created(id);
  return id;
}

CommandVerdict WorldBase::command_retreat(RobotId id) {
  telemetry_.reset();
  if (id >= stats_.size()) {
    ++commands_.rejected_unknown;
    return CommandVerdict::unknown_robot;
  }
  switch (stats_[id].phase) {
    case Phase::inside:
      stats_[id].phase = Phase::retreating;
      on_retreat(id);
      ++commands_.accepted;
      return CommandVerdict::accepted;
    case Phase::retreating:
      ++commands_.already_retreating;
      return CommandVerdict::already_retreating;
    case Phase::waiting:
    case Phase::departed:
      break;
  }
  ++commands_.rejected_not_inside;
  return CommandVerdict::not_inside;
}

const RobotStats& WorldBase::robot_stats(RobotId id) const {
  if (id >= stats_.size()) {
    throw std::out_of_range("robot_stats: unknown robot id " + std::to_string(id));
  }
  return stats_[id];
}

void WorldBase::depart(RobotId id, double time) {
  stats_[id].phase = Phase::departed;
  stats_[id].departed_at = time;
  in_contact_[id] = 0;
  departed_this_tick_[id] = 1;
}

void WorldBase::build_frames() {
  telemetry_.reset();
  frames_.clear();
  while (framed_ < stats_.size() && stats_[framed_].phase == Phase::departed && departed_this_tick_[framed_] == 0) {
    ++framed_;
  }
  for (auto id = static_cast<RobotId>(framed_); id < stats_.size(); ++id) {
    if (stats_[id].phase == Phase::departed && departed_this_tick_[id] == 0) {
      continue;
    }
    frames_.push_back(
        {id, tick_, time_, stats_[id].phase, in_contact_[id] != 0, onsets_since_frame_[id]});
    onsets_since_frame_[id] = 0;
    departed_this_tick_[id] = 0;
  }
}

Telemetry WorldBase::telemetry() const {
  if (telemetry_) {
    return *telemetry_;
  }
  Telemetry& t = telemetry_.emplace();
  t.tick = tick_;
  t.time = time_;
  for (; summed_ < stats_.size() && stats_[summed_].phase == Phase::departed; ++summed_) {
    for (std::size_t k = 0; k < task_state_count; ++k) summed_time_[k] += stats_[summed_].state_time[k];
  }
  t.departed = static_cast<decltype(t.departed)>(summed_);
  t.state_time = summed_time_;
  for (auto id = static_cast<RobotId>(summed_); id < stats_.size(); ++id) {
    const RobotStats& s = stats_[id];
    switch (s.phase) {
      case Phase::waiting:
        ++t.waiting;
        break;
      case Phase::inside:
        ++t.inside;
        ++t.state_counts[static_cast<std::size_t>(task_state(s.loaded, in_contact_[id] != 0))];
        break;
      case Phase::retreating:
        ++t.retreating;
        break;
      case Phase::departed:
        ++t.departed;
        break;
    }
    for (std::size_t k = 0; k < task_state_count; ++k) {
      t.state_time[k] += s.state_time[k];
    }
  }
  t.true_density = static_cast<double>(t.inside + t.retreating) / domain_.area();
  t.deliveries = deliveries_;
  t.onsets = onsets_;
  t.commands = commands_;
  return t;
}

}  // namespace retreat::physics::detail
