#include "retreat/agent/frame_verdict.hpp"

namespace retreat::agent {

std::string_view to_string(FrameVerdict verdict) {
  switch (verdict) {
    case FrameVerdict::accepted:
      return "accepted";
    case FrameVerdict::wrong_robot:
      return "wrong_robot";
    case FrameVerdict::stale_tick:
      return "stale_tick";
    case FrameVerdict::duplicate_tick:
      return "duplicate_tick";
    case FrameVerdict::bad_time:
      return "bad_time";
  }
  return "unknown";
}

std::uint64_t FrameCounts::dropped() const noexcept {
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    if (i != static_cast<std::size_t>(FrameVerdict::accepted)) {
      total += counts_[i];
    }
  }
  return total;
}

}  // namespace retreat::agent
