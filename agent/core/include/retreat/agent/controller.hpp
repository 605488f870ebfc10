#pragma once
/// @file
/// The interface of a named retreat controller: one decision step's probability of leaving.

#include <cstdint>
#include <memory>
#include <string_view>

#include "retreat/agent/agent_params.hpp"
#include "retreat/agent/onset_window.hpp"
#include "retreat/model/params.hpp"

namespace retreat::agent {

/// Everything a controller may use at one decision step: only the robot's own information.
struct ControllerInput {
  double time;                      ///< t_k on the robot's own clock [s] (the frame's time if
                                    ///< within 1e-9·dt of it)
  double time_inside;               ///< t_k − t_entry = k·dt, time since own entry [s], at
                                    ///< least Controller::first_decision_after (L for `paper`)
  std::uint64_t onsets_in_window;   ///< y_iL(t_k), onsets in [t_k − L, t_k] [-]; before L that
                                    ///< is every onset since entry (none are counted outside D)
  double L;                         ///< window length L [s]
  double dt;                        ///< decision period dt [s]
  double lambda_hat;                ///< λ̂ = y_iL / (4δ(4/π)vL) [robots/m²]
  double lambda_star;               ///< λ* = model::lambda_star(model) [robots/m²], the same
                                    ///< at every step (the agent computes it once)
  const model::ModelParams& model;  ///< the model's parameters (λ_p, λ_d, C, δ, v, ρ)
  const AgentParams& agent;         ///< the agent's parameters (L, dt, K_p, λ_in)
  const OnsetWindow& window;        ///< the robot's own onset history (see OnsetWindow::entries)
};

/// A named rule turning the robot's own information into a retreat probability for one step.
/// Implementations are registered by name in controller_registry.cpp. They draw no random
/// numbers: the agent owns the generator and flips the coin.
///
/// Each robot's agent owns its own instance and calls it once per decision step, in time order.
/// A controller may keep state, but only state built from the inputs it has been given: the
/// ControllerInput of this and earlier steps is all it ever sees (no transport, no other robot,
/// no ground truth; the agent_core library cannot even link them).
class Controller {
 public:
  virtual ~Controller() = default;

  /// Probability of retreating at this step [-]. May fall outside [0, 1]; the agent clamps it.
  /// Must not be NaN. Called once per decision step with non-decreasing `input.time`.
  virtual double retreat_probability(const ControllerInput& input) = 0;

  /// Time inside D from which this controller decides [s], finite and >= 0: the agent asks it
  /// (and flips a coin) at every step k with k·dt >= this, from t_entry on. The paper's loop waits
  /// until the first window lies wholly inside D ("t > L"), and so do the controllers built on
  /// it; a controller that decides from a partial window returns less.
  virtual double first_decision_after(const AgentParams& agent) const { return agent.L; }

  /// The registered name (`paper`, ...), as written in the scenario's `agent.controller`.
  virtual std::string_view name() const = 0;

  /// Whether the chance at a step, once the window is full (time_inside >= L), is a function of
  /// the window count and the parameters alone: no state, no time. The experiments' exact chain
  /// then predicts the rule (deploy/experiment/prediction.cpp). Tested for every rule that says so.
  virtual bool count_only() const { return false; }

  /// Whether the rule corrects its estimate for a known sensor: reads `agent.missed_onsets` and
  /// `agent.false_onsets` (the noise experiment compares it told and not told). Tested both ways
  /// for every registered rule.
  virtual bool corrects_sensor() const { return false; }

  /// A copy of this controller, state and all, for looking ahead (RetreatAgent::plan): stepping
  /// the copy leaves this one unchanged.
  virtual std::unique_ptr<Controller> clone() const = 0;

 protected:
  Controller() = default;
  Controller(const Controller&) = default;
  Controller& operator=(const Controller&) = default;
  Controller(Controller&&) = default;
  Controller& operator=(Controller&&) = default;
};

}  // namespace retreat::agent
