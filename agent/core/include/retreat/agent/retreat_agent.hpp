#pragma once
/// @file
/// One robot's decision layer: Algorithm 1 of the paper, driven by the robot's own frames.

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "retreat/agent/agent_params.hpp"
#include "retreat/agent/controller.hpp"
#include "retreat/agent/frame_verdict.hpp"
#include "retreat/agent/observation.hpp"
#include "retreat/agent/onset_window.hpp"
#include "retreat/model/params.hpp"

namespace retreat::agent {

/// What one call of RetreatAgent::on_frame did.
struct FrameResult {
  FrameVerdict verdict = FrameVerdict::accepted;  ///< accepted, or why the frame was dropped
  bool retreat_now = false;  ///< this frame's steps produced the retreat decision
  bool retreating = false;   ///< the agent has decided to retreat (now or before; sticky)
};

/// When a producer's frames are, as the producer computes it: frame `tick` is at
/// static_cast<double>(tick · multiplier) · period. The arena's worlds keep such clocks (kinetic:
/// 1 × the tick period; physical: the physics steps per tick × the physics step), so an agent
/// told the clock knows its coming frames' times bit for bit, as it must to look ahead exactly.
struct FrameClock {
  std::int64_t multiplier = 1;  ///< clock steps per frame tick, >= 1
  double period = 0.0;          ///< one clock step [s], finite and > 0

  /// The time of frame @p tick [s].
  double time(std::int64_t tick) const noexcept { return static_cast<double>(tick * multiplier) * period; }
};

/// The last tick in @p from .. @p to at which @p holds, for a condition that holds up to some tick
/// and never after it (as a threshold on the times of frames on a FrameClock does); @p from − 1 if
/// it does not hold at @p from. A bisection: O(log(to − from)) evaluations.
template <typename Condition>
std::int64_t last_tick_where(std::int64_t from, std::int64_t to, Condition holds) {
  if (!holds(from)) return from - 1;
  if (holds(to)) return to;
  std::int64_t lo = from;  // holds
  std::int64_t hi = to;    // does not
  while (hi - lo > 1) {
    const std::int64_t mid = lo + (hi - lo) / 2;
    (holds(mid) ? lo : hi) = mid;
  }
  return lo;
}

/// An owned controller whose copies are clones (Controller::clone), so that an agent (and a
/// look-ahead copy of it) copies with the defaults: the copies go on alone.
class ControllerCopy {
 public:
  explicit ControllerCopy(std::unique_ptr<Controller> controller) : controller_(std::move(controller)) {}
  ControllerCopy(const ControllerCopy& other) : controller_(clone(other)) {}
  ControllerCopy& operator=(const ControllerCopy& other) {
    if (this != &other) controller_ = clone(other);
    return *this;
  }
  ControllerCopy(ControllerCopy&&) noexcept = default;
  ControllerCopy& operator=(ControllerCopy&&) noexcept = default;
  ~ControllerCopy() = default;

  Controller& operator*() const noexcept { return *controller_; }
  Controller* operator->() const noexcept { return controller_.get(); }

 private:
  static std::unique_ptr<Controller> clone(const ControllerCopy& c) {
    return c.controller_ ? c.controller_->clone() : nullptr;  // a moved-from one copies empty
  }
  std::unique_ptr<Controller> controller_;
};

/// What an agent will decide while its robot's input stays unchanged (RetreatAgent::plan).
struct Plan {
  /// The plan covers the frames after the last accepted one through this tick.
  std::int64_t through_tick = 0;
  /// The covered tick at whose frame the agent retreats (then through_tick is this tick);
  /// none: it stays through through_tick.
  std::optional<std::int64_t> retreat_tick;
};

/// The agent's state, for the status message and for tests.
struct AgentSnapshot {
  std::uint32_t robot_id = 0;
  std::optional<std::int64_t> tick;  ///< last accepted frame's tick (none before the first)
  double time = 0.0;                 ///< last accepted frame's time [s]
  std::optional<double> entry_time;  ///< t_entry: first accepted `inside` frame's time [s]
  bool deciding = false;             ///< has made a decision step and not stopped
  bool stopped = false;     ///< no more steps: decided, or the phase became retreating/departed
  bool retreating = false;  ///< has decided to retreat (sticky)
  /// y_iL at the last decision step [-]; before the first decision step, the onsets counted
  /// since entry (over partial_window seconds).
  std::uint64_t onsets_in_window = 0;
  /// λ̂ at the last decision step [robots/m²]; before the first decision step, the same estimate
  /// over the time inside so far (y / (4δ(4/π)v·partial_window); 0 at entry).
  double lambda_hat = 0.0;
  /// Before the first decision step: the time inside so far [s] that onsets_in_window and
  /// lambda_hat cover; 0 once decision steps are taken (they cover L).
  double partial_window = 0.0;
  double epsilon = 0.0;                ///< controller's rate at the last decision step, p/dt before
                                       ///< clamping [1/s] (ε(λ̂) for `paper`)
  std::uint64_t steps = 0;             ///< steps taken, k of the last step (with or without a coin)
  std::uint64_t decision_steps = 0;    ///< steps at which a coin was flipped (from L for `paper`)
  std::optional<double> decision_time;  ///< t_k of the step that decided to retreat [s]
  FrameCounts frames;                   ///< frames seen, per verdict
};

/// Algorithm 1 for one robot.
///
/// Frames are checked first (FrameVerdict); dropped frames are counted and change nothing.
/// The robot's entry time t_entry is the time of the first accepted frame with phase `inside`.
/// While the phase is `inside`, each frame's new onsets are recorded at the frame's time.
///
/// Steps are time-driven: step k (k = 1, 2, ...) happens at t_k = t_entry + k·dt, computed
/// as written (not accumulated), and every step with t_k <= frame time + 1e-9·dt is taken when
/// the frame arrives. One frame per dt gives one step per frame; late or bursty frames give
/// every missed step. A step within 1e-9·dt of the frame's time is evaluated at the frame's
/// time, so a frame's own onsets are in its own step's window.
///
/// At a step with k·dt >= L (within 1e-9·dt: the first coin is at t_k − t_entry = L, when the
/// window [t_k − L, t_k] first lies wholly inside D; the paper's loop reads "t > L"; a controller
/// may start earlier, Controller::first_decision_after):
/// y = onsets in [t_k − L, t_k], λ̂ = y / (4δ(4/π)vL), p = clamp(controller p, 0, 1), and the
/// agent retreats if its coin for step k, u_k = counter_uniform(seed, k) ~ U[0, 1), is < p
/// (always if p >= 1). The coin of step k depends on the seed and k alone, not on how many
/// coins were drawn before, so a look-ahead never changes a later decision.
/// After deciding, or once a frame's phase is `retreating` or `departed`, it takes no more
/// steps and draws no more numbers; it never re-enters.
///
/// Times are best counted from the run's start (as the arena's clock is): the 1e-9·dt
/// tolerance must exceed the rounding of the producer's clock.
class RetreatAgent {
 public:
  /// @param robot_id the robot whose frames this agent acts on.
  /// @param model the model's parameters (validated).
  /// @param agent the agent's parameters (validated).
  /// @param controller the controller; nullptr means make_controller(agent.controller).
  /// @param seed key of the agent's coins; pass
  ///        `retreat::seed_for(scenario_seed, robot_id, Stream::agent_decision)`.
  /// @throws std::invalid_argument if a parameter is out of range.
  explicit RetreatAgent(std::uint32_t robot_id = 0, model::ModelParams model = {},
                        AgentParams agent = {}, std::unique_ptr<Controller> controller = nullptr,
                        std::uint64_t seed = 0);

  /// Checks @p frame, then (if accepted) records its onsets and takes every due step.
  FrameResult on_frame(const Observation& frame);

  /// Looks ahead: what this agent decides if frames last+1 .. last+@p horizon (last: the last
  /// accepted frame's tick) arrive one per tick at @p clock's times with the last frame's phase
  /// and no new onsets, that is, while its robot's input stays unchanged. Computed on a copy
  /// (the controller's too), so this agent is untouched, and since step k's coin depends on the
  /// seed and k alone, feeding it those frames later gives exactly the plan's decisions; a frame
  /// that differs (an onset, a phase change) voids the plan from its tick on and is simply
  /// handled as it comes. An agent not yet inside, or stopped, decides nothing: it stays.
  /// @throws std::logic_error before any accepted frame.
  /// @throws std::invalid_argument if @p horizon < 1, if @p clock is not a valid clock, or if it
  ///         puts a covered frame before the last accepted frame's time.
  Plan plan(const FrameClock& clock, std::int64_t horizon) const;

  /// The last of the quiet frames last+1 .. @p through (on @p clock's times, with @p phase and
  /// no new onsets; last: the last accepted frame's tick) that take_quiet_frames takes at once:
  /// up to the frame before the first that would take a decision step, or would be refused, or
  /// is the first `inside` frame (entry). The last accepted tick if none; @p through if all.
  /// @throws std::logic_error before any accepted frame.
  /// @throws std::invalid_argument if @p clock is not a valid clock.
  std::int64_t quiet_through(const FrameClock& clock, RobotPhase phase, std::int64_t through) const;

  /// Takes the quiet frames last+1 .. quiet_through(@p clock, @p phase, @p through) in one go,
  /// leaving the agent exactly as on_frame would, frame by frame (the same counts, steps and
  /// last frame; no such frame decides anything). Costs O(log n), not n frames: while nothing
  /// reaches a robot before its first decision step (L inside for `paper`), or while it waits
  /// or has stopped, its covered frames need no stepping. Returns the last tick taken.
  std::int64_t take_quiet_frames(const FrameClock& clock, RobotPhase phase, std::int64_t through);

  /// Whether the agent has decided to retreat (sticky).
  bool retreating() const noexcept { return decided_; }
  /// Whether the agent takes no more steps.
  bool stopped() const noexcept { return stopped_; }
  /// The agent's state for the status message.
  AgentSnapshot status() const;

  std::uint32_t robot_id() const noexcept { return robot_id_; }
  const model::ModelParams& model_params() const noexcept { return model_; }
  const AgentParams& agent_params() const noexcept { return agent_; }
  const Controller& controller() const noexcept { return *controller_; }
  const OnsetWindow& window() const noexcept { return window_; }
  const FrameCounts& frames() const noexcept { return frames_; }

 private:
  FrameVerdict check(const Observation& frame) const;
  bool take_due_steps(double frame_time);
  bool decide(double time, double time_inside);

  std::uint32_t robot_id_;
  model::ModelParams model_;
  AgentParams agent_;
  ControllerCopy controller_;  // copied by Controller::clone: a copied agent goes on alone
  std::uint64_t coin_key_;  // counter_uniform(coin_key_, k) is step k's coin
  OnsetWindow window_;
  double tolerance_;  // 1e-9·dt [s]
  double first_decision_;  // the controller's first_decision_after [s] (L for `paper`)
  double lambda_star_;  // model::lambda_star(model_), for every ControllerInput
  double mle_divisor_;  // model::mle_divisor(δ, v, L): λ̂ = y / it
  std::uint64_t first_decision_step_ = 1;  // the first k whose step decides (k·dt + 1e-9·dt >= first_decision_)

  FrameCounts frames_;
  std::optional<std::int64_t> last_tick_;
  double last_time_ = 0.0;
  std::optional<double> entry_time_;
  std::uint64_t next_step_ = 1;  // k of the next step
  std::uint64_t decision_steps_ = 0;
  bool decided_ = false;
  bool stopped_ = false;
  std::optional<double> decision_time_;
  std::uint64_t last_onsets_ = 0;
  double last_lambda_hat_ = 0.0;
  double last_epsilon_ = 0.0;
};

}  // namespace retreat::agent
