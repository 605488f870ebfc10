#pragma once
/// @file
/// Sliding-window counter of encounter onsets, y_iL(t) of the paper.

#include <cstdint>
#include <deque>

namespace retreat::agent {

/// Counts encounter onsets in the closed window [t − L, t] of the robot's own time.
///
/// Boundary rule: an onset at time u is counted at query time t iff t − L <= u <= t, both
/// compared in double precision with t − L computed as written. So an onset exactly at t − L
/// and an onset exactly at t are both counted; one at t − L − 1e-9 is not.
///
/// Onsets are added at non-decreasing times and queried at non-decreasing times. A query
/// evicts every onset older than t − L for good, which keeps the cost O(1) amortised per
/// onset. Onsets added at times later than a query time are kept and not counted by it
/// (a frame's onsets may be added before the steps that fall just before that frame).
class OnsetWindow {
 public:
  /// Onsets recorded at one instant.
  struct Entry {
    double time = 0.0;        ///< onset time [s]
    std::uint64_t count = 0;  ///< onsets at that time, >= 1
  };

  /// @param length window length L [s], finite and > 0.
  /// @throws std::invalid_argument if @p length is not finite and > 0.
  explicit OnsetWindow(double length);

  /// Records @p count onsets at @p time [s]. Does nothing if @p count is 0.
  /// @throws std::invalid_argument if @p time is not finite or is earlier than the last
  ///         recorded onset.
  void add(double time, std::uint64_t count = 1);

  /// y_iL(t): onsets in [t − L, t]. Evicts onsets older than t − L.
  /// @param t query time [s], not earlier than the previous query.
  /// @throws std::invalid_argument if @p t is not finite or earlier than the previous query.
  std::uint64_t count_at(double t);

  /// Window length L [s].
  double length() const noexcept { return length_; }

  /// Onsets currently held (not yet evicted), including any later than the last query [-].
  std::uint64_t held() const noexcept { return held_; }

  /// Held onsets, oldest first: at least every onset in [t − L, ∞) for the last query t.
  /// For controllers that look at the onset history, not just the count.
  const std::deque<Entry>& entries() const noexcept { return entries_; }

 private:
  double length_;
  std::deque<Entry> entries_;
  std::uint64_t held_ = 0;
  double last_onset_ = 0.0;  ///< entries_.back().time while entries_ is not empty
  bool queried_ = false;
  double last_query_ = 0.0;
};

}  // namespace retreat::agent
