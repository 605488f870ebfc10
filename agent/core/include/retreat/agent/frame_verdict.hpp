#pragma once
/// @file
/// What the agent did with a frame: accepted it, or dropped it and why.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace retreat::agent {

/// Outcome of checking one Observation. Dropped frames are counted and never acted on.
/// Checks run in this order and the first failing one names the verdict: robot id; time
/// finite and >= 0; tick against the last accepted tick; time against the last accepted time.
enum class FrameVerdict : std::uint8_t {
  accepted,        ///< acted on
  wrong_robot,     ///< robot_id is not this agent's robot
  stale_tick,      ///< tick lower than the last accepted tick
  duplicate_tick,  ///< tick equal to the last accepted tick
  bad_time,        ///< time is NaN, infinite, negative, or earlier than the last accepted time
};

/// Number of FrameVerdict values.
inline constexpr std::size_t frame_verdict_count = 5;

/// Lower-case name of @p verdict (`accepted`, `wrong_robot`, ...).
std::string_view to_string(FrameVerdict verdict);

/// Frames seen, per verdict.
class FrameCounts {
 public:
  /// Frames that got @p verdict.
  std::uint64_t operator[](FrameVerdict verdict) const noexcept {
    return counts_[static_cast<std::size_t>(verdict)];
  }
  /// Frames accepted.
  std::uint64_t accepted() const noexcept { return (*this)[FrameVerdict::accepted]; }
  /// Frames dropped for any reason.
  std::uint64_t dropped() const noexcept;
  /// Counts one frame with @p verdict.
  void count(FrameVerdict verdict) noexcept { ++counts_[static_cast<std::size_t>(verdict)]; }
  /// Counts @p frames frames with @p verdict.
  void count(FrameVerdict verdict, std::uint64_t frames) noexcept {
    counts_[static_cast<std::size_t>(verdict)] += frames;
  }

  bool operator==(const FrameCounts& other) const noexcept { return counts_ == other.counts_; }
  bool operator!=(const FrameCounts& other) const noexcept { return !(*this == other); }

 private:
  std::array<std::uint64_t, frame_verdict_count> counts_{};
};

}  // namespace retreat::agent
