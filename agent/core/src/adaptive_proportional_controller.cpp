#include "retreat/agent/adaptive_proportional_controller.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/agent/confident_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

AdaptiveSpan::AdaptiveSpan(double z) : z_(z) { check_confidence_z(z); }

void AdaptiveSpan::take_in(const ControllerInput& input) {
  const auto& held = input.window.entries();
  // Onsets at times before last_taken_ were taken in at an earlier step: start at it.
  auto onset = taken_any_ ? std::lower_bound(
                                held.begin(), held.end(), last_taken_,
                                [](const OnsetWindow::Entry& e, double t) { return e.time < t; })
                          : held.begin();
  for (; onset != held.end() && onset->time <= input.time; ++onset) {  // later ones: a later step's
    if (taken_any_ && onset->time == last_taken_) {
      // The same instant again: OnsetWindow adds onsets at that time to its entry.
      if (onset->count > at_last_taken_) {
        const std::uint64_t added = onset->count - at_last_taken_;
        total_ += added;
        if (!entries_.empty() && entries_.back().time == last_taken_) {
          entries_.back().through = total_;
        } else {
          forgotten_ += added;  // that instant lies before the span's start now
        }
        at_last_taken_ = onset->count;
      }
      continue;
    }
    total_ += onset->count;
    entries_.push_back(Entry{onset->time, total_});
    taken_any_ = true;
    last_taken_ = onset->time;
    at_last_taken_ = onset->count;
  }
}

std::uint64_t AdaptiveSpan::onsets_from(double time) const {
  const auto first = std::lower_bound(entries_.begin(), entries_.end(), time,
                                      [](const Entry& e, double t) { return e.time < t; });
  if (first == entries_.begin()) return onsets();
  return total_ - std::prev(first)->through;
}

double AdaptiveSpan::update(const ControllerInput& input) {
  if (!started_) {
    started_ = true;
    start_ = input.time - input.time_inside;  // the robot's entry
  }
  take_in(input);
  while (onsets() >= 2) {
    const double middle = input.time - (input.time - start_) / 2.0;
    const std::uint64_t later = onsets_from(middle);
    const double fall = static_cast<double>(onsets() - later) - static_cast<double>(later);
    if (!(fall > z_ * std::sqrt(static_cast<double>(onsets())))) break;
    start_ = middle;
    while (!entries_.empty() && entries_.front().time < middle) {
      forgotten_ = entries_.front().through;
      entries_.pop_front();
    }
    ++halvings_;
  }
  return input.time - start_;
}

AdaptiveProportionalController::AdaptiveProportionalController(double z) : z_(z), span_(z) {}

double AdaptiveProportionalController::retreat_probability(const ControllerInput& input) {
  const double span = span_.update(input);
  if (!(span > 0.0)) return 0.0;  // no time counted yet
  const double lambda_low = confident_density(span_.onsets(), span, input, z_);
  const double rate =
      model::epsilon(lambda_low, input.lambda_star, 0.0, input.agent.K_p);
  return rate * input.dt;
}

}  // namespace retreat::agent
