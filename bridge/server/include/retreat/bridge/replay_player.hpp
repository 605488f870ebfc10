#pragma once
/// @file
/// `retreat-bridge --replay FILE`: a finished run's observations (the arena's telemetry and
/// poses, the agents' statuses, from a recording) played into the dashboard's state instead of
/// DDS, with a position the page moves (GET/POST /api/replay): seek to any tick, play at a speed
/// (simulated seconds per wall second), pause. The state at a position is the state a live
/// bridge had after every sample up to that tick: the samples are applied again from the first
/// when the position moves back.

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "retreat/bridge/live_state.hpp"
#include "retreat/telemetry/aggregator.hpp"
#include "retreat/wire/messages.hpp"

namespace retreat::bridge {

struct ReplayPosition {
  std::int64_t first_tick = 0, last_tick = 0;  ///< the recording's span
  double first_time = 0.0, last_time = 0.0;    ///< [simulated s]
  std::int64_t tick = 0;                       ///< every sample up to this tick is applied
  double time = 0.0;                           ///< the simulated time of the position [s]
  bool playing = false;
  double speed = 1.0;                          ///< simulated seconds per wall second
};

class ReplayPlayer {
 public:
  /// Fastest play the page may ask for [simulated s per wall s].
  static constexpr double max_speed = 1000.0;

  /// Starts at the first tick, paused. @throws std::invalid_argument when there is nothing to
  /// play (no telemetry).
  ReplayPlayer(LiveState& state, telemetry::RunInfo run, std::vector<wire::ArenaTelemetry> telemetry,
               std::vector<wire::Poses> poses, std::vector<wire::AgentStatus> statuses);

  ReplayPosition position() const;
  /// Moves to @p tick (clamped to the span) and pauses.
  void seek(std::int64_t tick);
  /// Plays from the position at @p speed (0 < speed <= max_speed); from the start if at the end.
  void play(double speed);
  void pause();
  /// While playing, moves the position on by the wall time since the last call × speed; stops
  /// at the end. Call it often (the bridge's replay thread: every 50 ms).
  void advance(std::chrono::steady_clock::time_point now);

 private:
  struct Event {
    std::int64_t tick;
    double time;
    int order;  ///< statuses, then poses, then telemetry of one tick (as the receiver applies them)
    std::size_t index;
  };
  /// Applies the events up to simulated time @p time (under mutex_).
  void move_to(double time);

  LiveState& state_;
  telemetry::RunInfo run_;
  std::vector<wire::ArenaTelemetry> telemetry_;
  std::vector<wire::Poses> poses_;
  std::vector<wire::AgentStatus> statuses_;
  std::vector<Event> events_;  ///< sorted by time, then order
  mutable std::mutex mutex_;
  std::size_t applied_ = 0;  ///< events_[0, applied_) are in the state
  double time_ = 0.0;
  bool playing_ = false;
  double speed_ = 1.0;
  std::chrono::steady_clock::time_point last_advance_{};
};

}  // namespace retreat::bridge
