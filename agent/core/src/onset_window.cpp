#include "retreat/agent/onset_window.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "retreat/model/format_number.hpp"

namespace retreat::agent {

using model::format_number;

OnsetWindow::OnsetWindow(double length) : length_(length) {
  if (!(std::isfinite(length) && length > 0.0)) {
    throw std::invalid_argument("OnsetWindow length = " + format_number(length) +
                                ": must be finite and > 0 (s)");
  }
}

void OnsetWindow::add(double time, std::uint64_t count) {
  // last_onset_ rather than entries_.back(): most frames bring no onset, and this way they
  // touch nothing but this object.
  if (!std::isfinite(time) || (!entries_.empty() && time < last_onset_)) {
    throw std::invalid_argument("OnsetWindow::add: time " + format_number(time) +
                                " must be finite and not earlier than the last onset");
  }
  if (count == 0) {
    return;
  }
  if (!entries_.empty() && entries_.back().time == time) {
    entries_.back().count += count;
  } else {
    entries_.push_back(Entry{time, count});
  }
  last_onset_ = time;
  held_ += count;
}

std::uint64_t OnsetWindow::count_at(double t) {
  if (!std::isfinite(t) || (queried_ && t < last_query_)) {
    throw std::invalid_argument("OnsetWindow::count_at: time " + format_number(t) +
                                " must be finite and not earlier than the previous query");
  }
  queried_ = true;
  last_query_ = t;
  const double start = t - length_;
  while (!entries_.empty() && entries_.front().time < start) {
    held_ -= entries_.front().count;
    entries_.pop_front();
  }
  // Onsets after t (a frame's onsets added before the steps just before it): at most a few
  // entries at the back.
  std::uint64_t later = 0;
  for (auto it = entries_.rbegin(); it != entries_.rend() && it->time > t; ++it) {
    later += it->count;
  }
  return held_ - later;
}

}  // namespace retreat::agent
