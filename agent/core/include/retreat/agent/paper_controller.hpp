#pragma once
/// @file
/// The paper's controller, exactly as published (Algorithm 1 with eq. ε).

#include <memory>
#include <string_view>

#include "retreat/agent/controller.hpp"

namespace retreat::agent {

/// `paper`: leave with probability p = ε(λ̂)·dt, where
/// ε(λ̂) = (λ_in − K_p (λ* − λ̂)) / λ̂ above λ* and 0 otherwise, and
/// λ* = sqrt(C (1 + λ_d/λ_p) / (2δvλ_d)) from the model's parameters.
/// Uses the paper's MLE as written (no finite-population correction, MODEL.md §7.1).
class PaperController final : public Controller {
 public:
  /// The name this controller is registered under.
  static constexpr std::string_view registered_name = "paper";

  /// ε(λ̂)·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  std::string_view name() const override { return registered_name; }
  bool count_only() const override { return true; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<PaperController>(*this); }
};

}  // namespace retreat::agent
