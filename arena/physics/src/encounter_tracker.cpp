#include "retreat/physics/encounter_tracker.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace retreat::physics {
namespace {

constexpr double not_open = std::numeric_limits<double>::quiet_NaN();

std::uint64_t pair_key(RobotId low, RobotId high) {
  return (static_cast<std::uint64_t>(low) << 32) | high;
}

}  // namespace

void EncounterTracker::ensure(RobotId robot) {
  if (robot >= partners_.size()) {
    partners_.resize(static_cast<std::size_t>(robot) + 1);
    episode_start_.resize(static_cast<std::size_t>(robot) + 1, not_open);
  }
}

const std::vector<RobotId>& EncounterTracker::partners(RobotId robot) const {
  static const std::vector<RobotId> none;
  return robot < partners_.size() ? partners_[robot] : none;
}

void EncounterTracker::initialize(RobotId robot, const std::vector<RobotId>& sorted_partners) {
  ensure(robot);
  partners_[robot] = sorted_partners;
  episode_start_[robot] = not_open;
}

std::uint32_t EncounterTracker::update(RobotId robot, const std::vector<RobotId>& sorted_partners,
                                       double time) {
  ensure(robot);
  std::vector<RobotId>& old = partners_[robot];
  std::uint32_t onsets = 0;
  // Merge the two ascending lists: in new only = onset, in old only = end.
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < old.size() || j < sorted_partners.size()) {
    if (j == sorted_partners.size() || (i < old.size() && old[i] < sorted_partners[j])) {
      if (record_ && robot < old[i]) {
        const auto open = open_pairs_.find(pair_key(robot, old[i]));
        if (open != open_pairs_.end()) {
          records_.push_back({robot, old[i], open->second, time});
          open_pairs_.erase(open);
        }
      }
      ++i;
    } else if (i == old.size() || sorted_partners[j] < old[i]) {
      ++onsets;
      if (record_ && robot < sorted_partners[j]) {
        open_pairs_[pair_key(robot, sorted_partners[j])] = time;
      }
      ++j;
    } else {
      ++i;
      ++j;
    }
  }
  const bool was = !old.empty();
  const bool now = !sorted_partners.empty();
  if (!was && now) {
    episode_start_[robot] = time;
  } else if (was && !now) {
    if (record_ && !std::isnan(episode_start_[robot])) {
      records_.push_back({robot, no_robot, episode_start_[robot], time});
    }
    episode_start_[robot] = not_open;
  }
  old.assign(sorted_partners.begin(), sorted_partners.end());
  return onsets;
}

std::vector<ContactRecord> EncounterTracker::take_records() {
  std::vector<ContactRecord> out;
  out.swap(records_);
  return out;
}

}  // namespace retreat::physics
