#pragma once
/// @file
/// `confident`: the paper's controller applied to a lower confidence bound of the density, so
/// that the estimate's noise alone does not make robots leave (MODEL.md §7.3).

#include <cstdint>
#include <memory>
#include <string_view>

#include "retreat/agent/controller.hpp"

namespace retreat::agent {

/// Checks a confidence level: @p z standard deviations, finite and >= 0.
/// @throws std::invalid_argument naming @p z otherwise.
void check_confidence_z(double z);

/// The density estimate lowered by @p z Poisson standard deviations of the window count:
/// max(0, y − z·sqrt(y)) / (4δ(4/π)vL) [robots/m²], for y = @p onsets in a window of @p L [s].
/// z = 0 gives the paper's MLE λ̂.
double lower_confidence_density(std::uint64_t onsets, const model::ModelParams& model, double L,
                                double z);

/// `confident`: leave with probability ε(λ_low)·dt, where ε is the paper's one-sided rule and
///
///     λ_low = max(0, y − z·sqrt(y)) / (4δ(4/π)vL)
///
/// is the estimate lowered by z Poisson standard deviations of the window count y = y_iL(t).
/// The paper's rule acts on λ̂ itself: at λ = λ* the window holds ≈ 6.9 onsets, λ̂ has a relative
/// standard deviation of ≈ 38 %, it exceeds λ* about half the time, and each such step can
/// retreat. With z = 1 a robot leaves only once its own count is one standard deviation above
/// what λ* gives; below λ* it essentially never leaves. Uses only the robot's own window count.
class ConfidentController final : public Controller {
 public:
  /// The name this controller is registered under.
  static constexpr std::string_view registered_name = "confident";

  /// Standard deviations the count is lowered by [-].
  static constexpr double default_z = 1.0;

  /// @param z standard deviations of the Poisson count to subtract [-], finite and >= 0.
  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit ConfidentController(double z = default_z);

  /// ε(λ_low)·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  std::string_view name() const override { return registered_name; }
  bool count_only() const override { return true; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<ConfidentController>(*this); }

 private:
  double z_;
};

}  // namespace retreat::agent
