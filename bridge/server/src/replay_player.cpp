#include "retreat/bridge/replay_player.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace retreat::bridge {

ReplayPlayer::ReplayPlayer(LiveState& state, telemetry::RunInfo run, std::vector<wire::ArenaTelemetry> telemetry,
                           std::vector<wire::Poses> poses, std::vector<wire::AgentStatus> statuses)
    : state_(state),
      run_(std::move(run)),
      telemetry_(std::move(telemetry)),
      poses_(std::move(poses)),
      statuses_(std::move(statuses)) {
  if (telemetry_.empty()) throw std::invalid_argument("the recording has no arena telemetry to play");
  for (std::size_t i = 0; i < statuses_.size(); ++i) events_.push_back({statuses_[i].tick, statuses_[i].time, 0, i});
  for (std::size_t i = 0; i < poses_.size(); ++i) events_.push_back({poses_[i].tick, poses_[i].time, 1, i});
  for (std::size_t i = 0; i < telemetry_.size(); ++i) events_.push_back({telemetry_[i].tick, telemetry_[i].time, 2, i});
  std::stable_sort(events_.begin(), events_.end(), [](const Event& a, const Event& b) {
    return a.tick != b.tick ? a.tick < b.tick : a.order < b.order;
  });
  std::lock_guard lock(mutex_);
  time_ = events_.front().time;
  state_.update([&](telemetry::Aggregator& a) { a = telemetry::Aggregator(run_, a.options()); });
  move_to(time_);
}

ReplayPosition ReplayPlayer::position() const {
  std::lock_guard lock(mutex_);
  ReplayPosition p;
  p.first_tick = events_.front().tick;
  p.last_tick = events_.back().tick;
  p.first_time = events_.front().time;
  p.last_time = events_.back().time;
  p.tick = applied_ > 0 ? events_[applied_ - 1].tick : p.first_tick;
  p.time = time_;
  p.playing = playing_;
  p.speed = speed_;
  return p;
}

void ReplayPlayer::move_to(double time) {
  // The events of a tick share its time: up to `time` is up to a whole tick.
  const auto end = static_cast<std::size_t>(
      std::upper_bound(events_.begin(), events_.end(), time, [](double t, const Event& e) { return t < e.time; }) -
      events_.begin());
  if (end == applied_) return;
  state_.update([&](telemetry::Aggregator& a) {
    std::size_t from = applied_;
    if (end < applied_) {
      a = telemetry::Aggregator(run_, a.options());  // back: again from the first sample
      from = 0;
    }
    for (std::size_t i = from; i < end; ++i) {
      const auto& e = events_[i];
      switch (e.order) {
        case 0: a.on_status(statuses_[e.index]); break;
        case 1: a.on_poses(poses_[e.index]); break;
        default: a.on_telemetry(telemetry_[e.index]); break;
      }
    }
  });
  applied_ = end;
}

void ReplayPlayer::seek(std::int64_t tick) {
  std::lock_guard lock(mutex_);
  playing_ = false;
  // The time of the last event at or before `tick` (the first event's if before the span).
  const auto it = std::upper_bound(events_.begin(), events_.end(), tick,
                                   [](std::int64_t t, const Event& e) { return t < e.tick; });
  time_ = it == events_.begin() ? events_.front().time : std::prev(it)->time;
  move_to(time_);
}

void ReplayPlayer::play(double speed) {
  if (!std::isfinite(speed) || speed <= 0.0 || speed > max_speed) {
    throw std::invalid_argument("speed " + std::to_string(speed) + ": must be more than 0 and at most " +
                                std::to_string(static_cast<int>(max_speed)));
  }
  std::lock_guard lock(mutex_);
  if (applied_ == events_.size()) {  // at the end: from the start again
    time_ = events_.front().time;
    move_to(time_);
  }
  speed_ = speed;
  playing_ = true;
  last_advance_ = std::chrono::steady_clock::now();
}

void ReplayPlayer::pause() {
  std::lock_guard lock(mutex_);
  playing_ = false;
}

void ReplayPlayer::advance(std::chrono::steady_clock::time_point now) {
  std::lock_guard lock(mutex_);
  if (!playing_) return;
  const double wall = std::chrono::duration<double>(now - last_advance_).count();
  last_advance_ = now;
  time_ = std::min(time_ + std::max(0.0, wall) * speed_, events_.back().time);
  move_to(time_);
  if (applied_ == events_.size()) playing_ = false;
}

}  // namespace retreat::bridge
