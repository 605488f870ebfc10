#pragma once
/// @file
/// `confident-proportional` and `influx-matching`: rules that decide from the robot's entry on,
/// from a partial window, and keep the estimate's noise from removing robots (issue 14;
/// docs/experiments.md, "Rules that reach the optimum").

#include <cstdint>
#include <memory>
#include <string_view>

#include "retreat/agent/controller.hpp"

namespace retreat::agent {

/// The span the robot has counted onsets over at @p input's step: w = min(time inside, L) [s].
/// Before its first full window a robot has counted only since its entry (it counts nothing
/// outside D), so its window count y covers w, not L.
double counted_span(const ControllerInput& input);

/// The density the robot's own count supports with confidence: y lowered by @p z Poisson
/// standard deviations over the span it was counted in, corrected for the sensor's known
/// noise (agent.missed_onsets m, agent.false_onsets f: a sensor that keeps each onset with
/// chance 1 − m and adds spurious ones at rate f reports a Poisson count of mean
/// ((1 − m)·c·λ + f)·w):
///
///     λ_low = max(0, y − z·√y − f·w) / ((1 − m)·c · w),   w = counted_span(input),  c = 4δ(4/π)v
///
/// [robots/m²]. z = 0 is the maximum-likelihood estimate over the partial window (the paper's
/// λ̂ once w = L, with a perfect sensor).
/// @throws std::invalid_argument if @p z is not finite and >= 0.
double confident_partial_density(const ControllerInput& input, double z);

/// confident_partial_density for @p onsets counted over any @p span [s] (> 0) that ends at the
/// step: the same lowering and the same sensor correction, from @p input's model and agent.
/// @throws std::invalid_argument if @p z is not finite and >= 0.
double confident_density(std::uint64_t onsets, double span, const ControllerInput& input, double z);

/// `confident-proportional`: the paper's proportional term alone, on the confident estimate,
/// from the first step after entry:
///
///     ε = K_p (λ_low − λ*) / λ_low   if λ_low > λ*,   0 otherwise
///
/// i.e. the paper's ε with λ_in = 0 (MODEL.md §5), so that above λ* the mean-field density
/// obeys dλ/dt = K_p (λ* − λ) and below λ* nobody leaves. It compensates no influx: it is the
/// rule for a swarm whose robots stop arriving (the finite queue, a closed team), where the
/// configured λ_in is what drains `paper` (MODEL.md §7.2). Lowering by z = 1 standard deviation
/// (as `confident`) keeps a robot at or below λ* from leaving on noise alone (§7.3): at λ* a
/// full window holds ≈ 6.9 onsets and λ_low exceeds λ* only when y >= 11, P ≈ 0.1.
/// Deciding from entry costs nothing here: a young robot's λ_low over a short span is low (few
/// onsets, large √y), so it leaves only when its count is already high.
class ConfidentProportionalController final : public Controller {
 public:
  static constexpr std::string_view registered_name = "confident-proportional";
  static constexpr double default_z = 1.0;  ///< as `confident` [-]

  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit ConfidentProportionalController(double z = default_z);

  /// ε·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  /// The first step after entry (0: every step k >= 1).
  double first_decision_after(const AgentParams& /*agent*/) const override { return 0.0; }

  std::string_view name() const override { return registered_name; }
  bool count_only() const override { return true; }
  bool corrects_sensor() const override { return true; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<ConfidentProportionalController>(*this); }

 private:
  double z_;
};

/// `influx-matching`: a constant exit rate that matches the configured influx at the optimum,
/// plus `confident-proportional`'s term above it, from the first step after entry:
///
///     ε = λ_in / λ*  +  K_p (λ_low − λ*) / λ_low · [λ_low > λ*]
///
/// With arrivals at λ_in per m² and every robot leaving at λ_in/λ*, the robots inside form an
/// M/G/∞ queue: its mean is (arrival rate) × (mean stay) = λ_in|D| · λ*/λ_in = λ*|D| = N*,
/// whatever the physics, the encounter rate or the finite-population bias (no density estimate
/// enters this term). In mean field, dλ/dt = λ_in (1 − λ/λ*) below λ* and
/// −(λ_in/λ* + K_p)(λ − λ*) above it: λ* is the equilibrium and the proportional term only speeds
/// up the way down from a crowded start. It is the paper's ε evaluated at λ* (where
/// ε(λ*) = λ_in/λ*), made independent of the noisy λ̂ below λ*.
///
/// It trusts λ_in: a robot leaves at λ_in/λ* whether or not robots still arrive. Where arrivals
/// stop, the robots keep leaving (mean stay λ*/λ_in, 75 s in the Robotarium set-up) until none
/// is left: use it for a deployment whose influx lasts, set λ_in to that lasting influx
/// (with λ_in = 0 it is `confident-proportional`).
class InfluxMatchingController final : public Controller {
 public:
  static constexpr std::string_view registered_name = "influx-matching";

  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit InfluxMatchingController(double z = ConfidentProportionalController::default_z);

  /// ε·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  /// The first step after entry (0: every step k >= 1).
  double first_decision_after(const AgentParams& /*agent*/) const override { return 0.0; }

  std::string_view name() const override { return registered_name; }
  bool count_only() const override { return true; }
  bool corrects_sensor() const override { return true; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<InfluxMatchingController>(*this); }

 private:
  ConfidentProportionalController proportional_;
};

}  // namespace retreat::agent
