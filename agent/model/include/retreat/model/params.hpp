#pragma once
/// @file
/// The model's parameters (the `model:` section of a scenario file).

namespace retreat::model {

/// Parameters of the paper's encounter and transport model. Defaults are the Robotarium
/// experiment's (MODEL.md §6), with ρ = 2.44 from the paper's barrier-certificate fit.
struct ModelParams {
  double lambda_p = 1.32;  ///< λ_p: density of pick-up locations [1/m²]
  double lambda_d = 1.32;  ///< λ_d: density of drop-off locations [1/m²]
  double C = 0.03;         ///< C: cost weight of swarm size against output [-]
  double delta = 0.1;      ///< δ: sensing distance; encounter while ‖p_i − p_j‖ ≤ 2δ [m]
  double v = 0.1;          ///< v: mean robot speed [m/s]
  double rho = 2.44;       ///< ρ: encounter resolution rate, τ_r ~ Exp(ρ) [1/s]

  /// Checks that every field is finite and > 0.
  /// @throws std::invalid_argument with a one-line message naming the first bad field as in
  ///         the scenario file, its value and the valid range, e.g.
  ///         `model.delta = -0.1: must be > 0 (m)`.
  void validate() const;

  /// Visits the `model.*` keys in scenario-file order, `a(name, member)` (Drake's Serialize()).
  template <class Archive>
  void serialize(Archive& a) {
    a("lambda_p", lambda_p);
    a("lambda_d", lambda_d);
    a("C", C);
    a("delta", delta);
    a("v", v);
    a("rho", rho);
  }
};

}  // namespace retreat::model
