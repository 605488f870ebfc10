#pragma once
/// @file
/// `adaptive-proportional`: `confident-proportional` on a window that grows while the density
/// holds and forgets its older half when the count falls (issue 14; docs/experiments.md,
/// "A window that grows and forgets").

#include <cstdint>
#include <deque>
#include <memory>
#include <string_view>

#include "retreat/agent/controller.hpp"
#include "retreat/agent/early_confident_controllers.hpp"

namespace retreat::agent {

/// The span a robot counts its onsets over: from its entry, or from where it last found that its
/// count had fallen, to the step. Fed each step's onset history (OnsetWindow::entries), it keeps
/// the onsets since that start itself, so the span can outgrow the paper's window L.
///
/// At every step, while the span holds at least two onsets and the later half of it holds
/// clearly fewer than the earlier half,
///
///     y_earlier − y_later > z · √(y_earlier + y_later)
///
/// (z standard deviations of the difference of two Poisson counts of equal means), the earlier
/// half is forgotten for good: the span starts at its middle. A rise keeps the span (the robot
/// only leaves on it, and an old, lower count keeps it from leaving early).
class AdaptiveSpan {
 public:
  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit AdaptiveSpan(double z);

  /// Takes in the onsets of @p input.window.entries() up to @p input.time that are new since the
  /// last call, forgets halves as above, and returns the span [s] (> 0 from the first step after
  /// entry on). Calls come at non-decreasing input.time, one robot's steps in order.
  double update(const ControllerInput& input);

  /// Onsets in [start, t] after the last update [-].
  std::uint64_t onsets() const noexcept { return total_ - forgotten_; }
  /// Start of the span on the robot's clock after the last update [s].
  double start() const noexcept { return start_; }
  /// Times the span has been halved since entry [-].
  int halvings() const noexcept { return halvings_; }

 private:
  /// Onsets at one instant, with the running total of every onset taken in up to it.
  struct Entry {
    double time = 0.0;
    std::uint64_t through = 0;  ///< onsets taken in, this entry's included [-]
  };

  void take_in(const ControllerInput& input);
  std::uint64_t onsets_from(double time) const;  ///< held onsets at times >= time

  double z_;
  bool started_ = false;
  double start_ = 0.0;
  std::deque<Entry> entries_;    ///< onsets in [start_, last update], oldest first
  std::uint64_t total_ = 0;      ///< onsets taken in since entry
  std::uint64_t forgotten_ = 0;  ///< of which before start_
  bool taken_any_ = false;
  double last_taken_ = 0.0;          ///< time of the latest onsets taken in [s]
  std::uint64_t at_last_taken_ = 0;  ///< OnsetWindow's count at last_taken_, when taken in
  int halvings_ = 0;
};

/// `adaptive-proportional`: the paper's proportional term alone (λ_in = 0), from entry, on the
/// confident estimate over the adaptive span instead of a window of length L:
///
///     ε = K_p (λ_low − λ*) / λ_low  if λ_low > λ*, else 0,
///     λ_low = confident_density(y, w),  w, y = AdaptiveSpan's span and its onsets,  z = 1
///
/// It is `confident-proportional` with the window replaced. Where `confident-proportional`
/// re-estimates from the last L seconds at every step, a robot here keeps counting for as long
/// as its count holds, so at a steady density its count grows with its time inside and the
/// chance that noise alone puts λ_low above λ* shrinks with it: the exits that drain a closed
/// team at the optimum (MODEL.md §7.3) die out instead of going on at a steady rate. The halving
/// keeps the long window from holding the crowded past on the way down. Rule for a closed team
/// or a queue that empties, like `confident-proportional`; L plays no part.
class AdaptiveProportionalController final : public Controller {
 public:
  static constexpr std::string_view registered_name = "adaptive-proportional";

  /// @param z the lowering of the estimate and the halving test, in standard deviations.
  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit AdaptiveProportionalController(double z = ConfidentProportionalController::default_z);

  /// ε·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  /// The first step after entry (0: every step k >= 1).
  double first_decision_after(const AgentParams& /*agent*/) const override { return 0.0; }

  std::string_view name() const override { return registered_name; }
  bool corrects_sensor() const override { return true; }
  std::unique_ptr<Controller> clone() const override {
    return std::make_unique<AdaptiveProportionalController>(*this);
  }

  /// The span as of the last step, for tests and diagnostics.
  const AdaptiveSpan& span() const noexcept { return span_; }

 private:
  double z_;
  AdaptiveSpan span_;
};

}  // namespace retreat::agent
