#pragma once
/// @file
/// Bookkeeping shared by both worlds (private header): robot ids and phases, the queue and the
/// influx, retreat commands, frames, telemetry and per-robot statistics.

#include <array>
#include <deque>
#include <optional>
#include <vector>

#include "retreat/physics/domain.hpp"
#include "retreat/physics/influx.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/physics/world.hpp"

namespace retreat::physics::detail {

class WorldBase : public World {
 public:
  CommandVerdict command_retreat(RobotId id) final;
  const std::vector<RobotFrame>& frames() const final { return frames_; }
  Telemetry telemetry() const override;
  const RobotStats& robot_stats(RobotId id) const final;
  std::size_t robot_count() const final { return stats_.size(); }
  const WorldParams& params() const final { return params_; }

 protected:
  /// Derived constructors call init_population(), place the inside robots, then build_frames().
  explicit WorldBase(const WorldParams& params);

  /// Creates robots 0 .. robots_inside−1 (phase inside, entered at 0) and the queued ones.
  void init_population();

  /// Sizes the derived world's per-robot arrays for a new id.
  virtual void on_robot_created(RobotId id) = 0;
  /// Robot @p id was inside and has just been told to retreat (its phase is already set).
  virtual void on_retreat(RobotId id) = 0;

  /// Adds the arrivals due by @p time and lets queued robots enter, front first, while
  /// @p try_enter(id) succeeds (it returns false when there is no room now; they stay due).
  template <class TryEnter>
  void admit_arrivals(double time, TryEnter&& try_enter) {
    due_ += influx_.arrivals_until(time, world_rng_);
    if (queue_kind_ == QueueKind::finite && due_ > queue_.size()) {
      due_ = queue_.size();  // arrivals with nobody left to send are lost
    }
    while (due_ > 0 && !queue_.empty()) {
      const RobotId id = queue_.front();
      if (!try_enter(id)) {
        return;
      }
      queue_.pop_front();
      --due_;
      stats_[id].phase = Phase::inside;
      stats_[id].entered_at = time;
      if (queue_kind_ == QueueKind::endless) {
        queue_.push_back(create_robot());
      }
    }
  }

  /// Marks @p id departed at @p time (the derived world has removed it from the domain).
  void depart(RobotId id, double time);

  /// Adds @p count onsets for @p id (frame counter, statistics, total).
  void add_onsets(RobotId id, std::uint32_t count) {
    onsets_since_frame_[id] += count;
    stats_[id].onsets += count;
    onsets_ += count;
  }

  /// Rebuilds frames() for the current tick and resets the per-frame counters (and forgets the
  /// telemetry of the previous tick).
  void build_frames();

  RobotId create_robot();

  WorldParams params_;
  Domain domain_;
  Rng world_rng_;
  Influx influx_;
  QueueKind queue_kind_;
  std::vector<RobotStats> stats_;
  std::vector<std::uint8_t> in_contact_;
  std::vector<std::uint32_t> onsets_since_frame_;
  std::vector<std::uint8_t> departed_this_tick_;
  std::deque<RobotId> queue_;
  std::uint64_t due_ = 0;
  std::int64_t tick_ = 0;
  double time_ = 0.0;
  std::uint64_t deliveries_ = 0;
  std::uint64_t onsets_ = 0;
  CommandCounts commands_;
  std::vector<RobotFrame> frames_;

 private:
  /// telemetry() of the current tick, computed on first use: one pass over every robot, where
  /// a tick asks for it several times (the arena's tick, its clock, the recorder's row). Forgotten
  /// by build_frames() (a step) and command_retreat() (phases and counters change).
  mutable std::optional<Telemetry> telemetry_;
  /// An endless queue's robots depart roughly in the order they came, and a departed robot's
  /// stats never change again: robots 0 .. summed_ − 1 have departed, and summed_time_ is their
  /// state_time summed in id order, where telemetry()'s sum over every robot resumes (the same
  /// additions in the same order: the same bits).
  mutable std::size_t summed_ = 0;
  mutable std::array<double, task_state_count> summed_time_{};
  /// Robots 0 .. framed_ − 1 have departed and had their last frame: build_frames() starts after them.
  std::size_t framed_ = 0;
};

}  // namespace retreat::physics::detail
