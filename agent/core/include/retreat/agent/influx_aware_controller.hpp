#pragma once
/// @file
/// `influx-aware` and `confident-influx-aware`: the paper's controller with λ_in replaced by the
/// influx the robot itself observes, so that it stops compensating an influx that has ended
/// (MODEL.md §7.2).

#include <deque>
#include <memory>
#include <string_view>

#include "retreat/agent/controller.hpp"

namespace retreat::agent {

/// `influx-aware`: leave with probability ε(λ̂; λ̂_in)·dt, the paper's one-sided rule with the
/// configured λ_in replaced by an estimate of the influx that is actually happening:
///
///     λ̂_in(t) = clamp( (λ̂(t) − λ̂(t − L)) / L  +  mean over (t − L, t) of ε·λ̂ ,  0, λ_in )
///
/// The first term is the net change of density the robot has measured between two disjoint
/// windows of its own onsets; the second is the outflow its own retreat rate would cause if
/// every robot retreated at that rate, so their sum estimates what came in. While robots keep
/// entering the estimate approaches λ_in and the rule is the paper's; once they stop it falls
/// to ≈ 0 and only the proportional term K_p (λ̂ − λ*) remains. λ_in stays the ceiling: the
/// robot never compensates more than the deployment's configured influx.
///
/// Until the robot has been inside for 2L it has no earlier window to compare with, and it
/// compensates nothing (λ̂_in = 0): without evidence of an influx it does not assume one. This
/// is where the paper's rule drains the Robotarium swarm (12 robots at its first decision, no
/// robot entering any more; docs/experiments.md).
///
/// `confident-influx-aware` is the same rule acting on the lowered estimate of the `confident`
/// controller (lower_confidence_density with z = 1) in ε; the influx estimate uses λ̂ itself.
///
/// Uses only the robot's own onset counts, its own decisions and the configured parameters.
/// Keeps one record per decision step over the last L (L/dt records, 3,000 in the Robotarium
/// set-up).
class InfluxAwareController final : public Controller {
 public:
  /// The names this controller is registered under (z = 0 and z = 1).
  static constexpr std::string_view registered_name = "influx-aware";
  static constexpr std::string_view confident_name = "confident-influx-aware";

  /// @param z standard deviations the window count is lowered by in ε [-] (0: λ̂ itself).
  /// @param name the registered name it answers to.
  /// @throws std::invalid_argument if @p z is not finite and >= 0.
  explicit InfluxAwareController(double z = 0.0, std::string_view name = registered_name);

  /// ε(λ; λ̂_in)·dt [-] (>= 0; may exceed 1, the agent clamps).
  double retreat_probability(const ControllerInput& input) override;

  std::string_view name() const override { return name_; }
  std::unique_ptr<Controller> clone() const override { return std::make_unique<InfluxAwareController>(*this); }

  /// The influx estimate used at the last step [robots/(m²·s)].
  double last_influx_estimate() const noexcept { return last_influx_; }

 private:
  /// One decision step's own record.
  struct Step {
    double time;        ///< t_k [s]
    double lambda_hat;  ///< λ̂(t_k) [robots/m²]
    double outflow;     ///< min(ε, 1/dt)·λ̂ at t_k [robots/(m²·s)]
  };

  double z_;
  std::string_view name_;
  std::deque<Step> steps_;     ///< steps since t − L, oldest first; steps_[0] is the latest
                               ///< step at or before t − L once there is one
  double outflow_sum_ = 0.0;   ///< sum of steps_[1..].outflow
  double last_influx_ = 0.0;
};

}  // namespace retreat::agent
