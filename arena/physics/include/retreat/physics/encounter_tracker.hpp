#pragma once
/// @file
/// Encounter bookkeeping (MODEL.md §5, §7.4): which robots are within 2δ of each robot, the
/// onsets (a partner that was not within 2δ at the previous sample), and contact intervals.

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// One contact interval. For a pair, robot < other and the interval is the time the two centres
/// stayed within 2δ; for a robot-level episode, other == no_robot and the interval is the time
/// the robot had at least one partner within 2δ (the CTMC's fc/lc sojourn, MODEL.md §3).
struct ContactRecord {
  RobotId robot = 0;
  RobotId other = no_robot;
  double start = 0.0;  ///< sample time of the onset [s]
  double end = 0.0;    ///< sample time of the first sample without contact [s]
};

/// Per-robot partner sets, updated once per sample. An onset is counted when a partner appears
/// that was absent at the previous sample: once per new pair, and again if the pair separated
/// past 2δ and closed in again. Sampling is at the physics step; contacts shorter than one step
/// may be missed, which is negligible when 2·max_speed·physics_dt ≪ 2δ (validated ≤ δ/2).
class EncounterTracker {
 public:
  /// @p record: keep completed ContactRecords until take_records().
  explicit EncounterTracker(bool record) : record_(record) {}

  /// Sets @p robot's partners at the first sample (t = 0) without counting onsets or opening
  /// records: contacts that were never seen to begin are not encounters.
  void initialize(RobotId robot, const std::vector<RobotId>& sorted_partners);

  /// Replaces @p robot's partner set with @p sorted_partners (ascending, no duplicates) sampled
  /// at @p time; returns the number of onsets (partners not present before). Pair records are
  /// kept by the lower id of the pair, so both robots of a pair must be updated at each sample.
  std::uint32_t update(RobotId robot, const std::vector<RobotId>& sorted_partners, double time);

  /// True if @p robot has a partner now.
  bool in_contact(RobotId robot) const {
    return robot < partners_.size() && !partners_[robot].empty();
  }

  /// The current partners of @p robot (ascending).
  const std::vector<RobotId>& partners(RobotId robot) const;

  /// Completed records since the previous call, in completion order.
  std::vector<ContactRecord> take_records();

 private:
  void ensure(RobotId robot);
  bool record_;
  std::vector<std::vector<RobotId>> partners_;
  std::vector<double> episode_start_;  // NaN: no open episode (or its onset was not observed)
  std::unordered_map<std::uint64_t, double> open_pairs_;  // (robot << 32 | other) -> onset
  std::vector<ContactRecord> records_;
};

}  // namespace retreat::physics
