#include "retreat/agent/retreat_agent.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {
namespace {

/// Steps within this fraction of dt of a frame's time belong to that frame: absorbs the
/// rounding between t_entry + k·dt and a producer's own clock (e.g. tick·dt).
constexpr double step_tolerance = 1e-9;

/// @p params after checking them (so that members are built from valid parameters only).
template <typename Params>
Params validated(Params params) {
  params.validate();
  return params;
}

/// Throws unless @p clock is a valid frame clock.
void check_clock(const FrameClock& clock) {
  if (clock.multiplier < 1 || !std::isfinite(clock.period) || clock.period <= 0.0) {
    throw std::invalid_argument("frame clock " + std::to_string(clock.multiplier) + " x " +
                                std::to_string(clock.period) +
                                " s: the multiplier must be >= 1 and the period finite and > 0");
  }
}

/// Doubles below this hold every integer exactly.
constexpr double exact_integers = 0x1p52;

/// The first step k >= 1 that decides, as take_due_steps tests it (a step with
/// k·dt + tolerance < first_decision does not). 1 if k is too large to find exactly: a step
/// taken for a deciding one only ends a quiet stretch early, which is always safe.
/// The first step k >= @p lower at which @p holds (a condition false up to some step and true
/// from it on), searched from @p estimate (used if above @p lower and exact as an integer).
template <typename Condition>
std::uint64_t first_step_where(std::uint64_t lower, double estimate, Condition holds) {
  std::uint64_t k = lower;
  if (estimate > static_cast<double>(lower) && estimate < exact_integers) {
    k = static_cast<std::uint64_t>(estimate);
  }
  while (k > lower && holds(k - 1)) --k;
  while (!holds(k)) ++k;
  return k;
}

std::uint64_t first_deciding_step(double first_decision, double dt, double tolerance) {
  const auto decides = [&](std::uint64_t k) { return !(static_cast<double>(k) * dt + tolerance < first_decision); };
  const double estimate = std::ceil((first_decision - tolerance) / dt);
  if (!(estimate < exact_integers)) return 1;
  return first_step_where(1, estimate, decides);
}

}  // namespace

RetreatAgent::RetreatAgent(std::uint32_t robot_id, model::ModelParams model, AgentParams agent,
                           std::unique_ptr<Controller> controller, std::uint64_t seed)
    : robot_id_(robot_id),
      model_(validated(model)),
      agent_(validated(std::move(agent))),
      controller_(controller ? std::move(controller) : make_controller(agent_.controller)),
      coin_key_(seed),
      window_(agent_.L),
      tolerance_(step_tolerance * agent_.dt),
      first_decision_(controller_->first_decision_after(agent_)),
      lambda_star_(model::lambda_star(model_)),
      mle_divisor_(model::mle_divisor(model_.delta, model_.v, agent_.L)) {
  if (!std::isfinite(first_decision_) || first_decision_ < 0.0) {
    throw std::invalid_argument("controller '" + std::string(controller_->name()) +
                                "' decides from time inside " + std::to_string(first_decision_) +
                                " s: must be finite and >= 0");
  }
  first_decision_step_ = first_deciding_step(first_decision_, agent_.dt, tolerance_);
}

Plan RetreatAgent::plan(const FrameClock& clock, std::int64_t horizon) const {
  if (!last_tick_) {
    throw std::logic_error("RetreatAgent::plan before any accepted frame");
  }
  if (horizon < 1) {
    throw std::invalid_argument("plan horizon = " + std::to_string(horizon) + ": must be >= 1 tick");
  }
  check_clock(clock);
  Plan plan;
  plan.through_tick = *last_tick_ + horizon;
  if (stopped_ || !entry_time_) {
    return plan;  // stopped, or waiting (entering is an input change): no decision to come
  }
  // Up to the first decision step the covered frames decide nothing: no copy, no stepping.
  const std::int64_t quiet = quiet_through(clock, RobotPhase::inside, plan.through_tick);
  if (quiet == plan.through_tick) {
    return plan;
  }
  RetreatAgent ahead(*this);
  ahead.take_quiet_frames(clock, RobotPhase::inside, quiet);
  Observation frame;
  frame.robot_id = robot_id_;
  frame.phase = RobotPhase::inside;
  for (std::int64_t tick = quiet + 1; tick <= plan.through_tick; ++tick) {
    frame.tick = tick;
    frame.time = clock.time(tick);
    const FrameResult result = ahead.on_frame(frame);
    if (result.verdict != FrameVerdict::accepted) {
      throw std::invalid_argument("frame clock puts tick " + std::to_string(tick) + " at " +
                                  std::to_string(frame.time) + " s, before the last frame's " +
                                  std::to_string(last_time_) + " s");
    }
    if (result.retreat_now) {
      plan.retreat_tick = tick;
      plan.through_tick = tick;
      break;
    }
  }
  return plan;
}

std::int64_t RetreatAgent::quiet_through(const FrameClock& clock, RobotPhase phase, std::int64_t through) const {
  if (!last_tick_) {
    throw std::logic_error("RetreatAgent::quiet_through before any accepted frame");
  }
  check_clock(clock);
  const std::int64_t last = *last_tick_;
  // A frame check() would refuse (or, on a clock that never goes back, the frames after it):
  // frame by frame, so that it is refused and counted as on_frame does.
  if (through <= last || !(clock.time(last + 1) >= last_time_) || !std::isfinite(clock.time(through))) {
    return last;
  }
  if (stopped_ || phase != RobotPhase::inside) {
    return through;  // on_frame only counts such frames: they take no step
  }
  if (!entry_time_) {
    return last;  // the first `inside` frame is the entry: frame by frame
  }
  // Step k is taken by a frame at time f unless t_k > f + tolerance (take_due_steps, the same
  // expressions); the steps before the first deciding one decide nothing. So the frames before
  // the one that takes that step are quiet; frame times never go back, so a bisection finds it.
  const std::uint64_t k = std::max(next_step_, first_decision_step_);
  const double decisive = *entry_time_ + static_cast<double>(k) * agent_.dt;
  const auto quiet = [&](std::int64_t tick) { return decisive > clock.time(tick) + tolerance_; };
  // Once the agent decides, every frame does: then the first test answers (last).
  return last_tick_where(last + 1, through, quiet);
}

std::int64_t RetreatAgent::take_quiet_frames(const FrameClock& clock, RobotPhase phase, std::int64_t through) {
  const std::int64_t to = quiet_through(clock, phase, through);
  const std::int64_t last = *last_tick_;
  if (to == last) {
    return last;
  }
  frames_.count(FrameVerdict::accepted, static_cast<std::uint64_t>(to - last));
  last_tick_ = to;
  last_time_ = clock.time(to);
  if (phase == RobotPhase::retreating || phase == RobotPhase::departed) {
    stopped_ = true;
  } else if (phase == RobotPhase::inside && !stopped_) {
    // What take_due_steps does with these frames: every step due by the last one is taken, and
    // none of them decides (quiet_through), so only k moves on, to the first step not yet due.
    const double entry = *entry_time_;
    const auto not_due = [&](std::uint64_t k) {
      return entry + static_cast<double>(k) * agent_.dt > last_time_ + tolerance_;
    };
    next_step_ = first_step_where(next_step_, std::floor((last_time_ + tolerance_ - entry) / agent_.dt), not_due);
  }
  return to;
}

FrameVerdict RetreatAgent::check(const Observation& frame) const {
  if (frame.robot_id != robot_id_) {
    return FrameVerdict::wrong_robot;
  }
  if (!std::isfinite(frame.time) || frame.time < 0.0) {
    return FrameVerdict::bad_time;
  }
  if (last_tick_) {
    if (frame.tick < *last_tick_) {
      return FrameVerdict::stale_tick;
    }
    if (frame.tick == *last_tick_) {
      return FrameVerdict::duplicate_tick;
    }
    if (frame.time < last_time_) {
      return FrameVerdict::bad_time;
    }
  }
  return FrameVerdict::accepted;
}

FrameResult RetreatAgent::on_frame(const Observation& frame) {
  FrameResult result;
  result.verdict = check(frame);
  frames_.count(result.verdict);
  if (result.verdict == FrameVerdict::accepted) {
    last_tick_ = frame.tick;
    last_time_ = frame.time;
    if (frame.phase == RobotPhase::retreating || frame.phase == RobotPhase::departed) {
      stopped_ = true;
    } else if (frame.phase == RobotPhase::inside && !stopped_) {
      if (!entry_time_) {
        entry_time_ = frame.time;
      }
      window_.add(frame.time, frame.new_onsets);
      result.retreat_now = take_due_steps(frame.time);
    }
  }
  result.retreating = decided_;
  return result;
}

bool RetreatAgent::take_due_steps(double frame_time) {
  while (!stopped_) {
    const double time_inside = static_cast<double>(next_step_) * agent_.dt;  // k·dt
    const double step_time = *entry_time_ + time_inside;                     // t_k
    if (step_time > frame_time + tolerance_) {
      return false;
    }
    ++next_step_;
    if (time_inside + tolerance_ < first_decision_) {
      continue;  // still filling the first window (L for `paper`): no decision
    }
    const double at = std::abs(step_time - frame_time) <= tolerance_ ? frame_time : step_time;
    if (decide(at, time_inside)) {
      return true;
    }
  }
  return false;
}

bool RetreatAgent::decide(double time, double time_inside) {
  const std::uint64_t onsets = window_.count_at(time);
  const double lambda_hat = model::mle_density(onsets, mle_divisor_);
  const ControllerInput input{time,       time_inside,  onsets, agent_.L, agent_.dt,
                              lambda_hat, lambda_star_, model_, agent_,   window_};
  const double raw = controller_->retreat_probability(input);
  if (std::isnan(raw)) {
    throw std::logic_error("controller '" + std::string(controller_->name()) +
                           "' returned a NaN retreat probability");
  }
  const double p = std::clamp(raw, 0.0, 1.0);
  ++decision_steps_;
  last_onsets_ = onsets;
  last_lambda_hat_ = lambda_hat;
  last_epsilon_ = raw / agent_.dt;

  // Step k's own coin (k = next_step_ − 1, the step being taken): a function of the key and k
  // alone, drawn whatever p is. counter_uniform never returns 1, so p >= 1 always retreats.
  const double u = retreat::counter_uniform(coin_key_, next_step_ - 1);
  if (u < p) {
    decided_ = true;
    stopped_ = true;
    decision_time_ = time;
  }
  return decided_;
}

AgentSnapshot RetreatAgent::status() const {
  AgentSnapshot s;
  s.robot_id = robot_id_;
  s.tick = last_tick_;
  s.time = last_time_;
  s.entry_time = entry_time_;
  s.deciding = decision_steps_ > 0 && !stopped_;
  s.stopped = stopped_;
  s.retreating = decided_;
  s.onsets_in_window = last_onsets_;
  s.lambda_hat = last_lambda_hat_;
  s.epsilon = last_epsilon_;
  if (decision_steps_ == 0 && entry_time_ && !stopped_) {
    // Before the first decision step (L for `paper`) nothing has been queried or evicted: every
    // onset held was counted since entry. Report that count and the estimate over the time
    // inside so far, so that a dashboard does not read 0 while onsets are being counted.
    const double inside = last_time_ - *entry_time_;
    s.onsets_in_window = window_.held();
    s.partial_window = inside;
    s.lambda_hat = inside > 0.0 ? model::mle_density(window_.held(), model_.delta, model_.v, inside) : 0.0;
  }
  s.steps = next_step_ - 1;
  s.decision_steps = decision_steps_;
  s.decision_time = decision_time_;
  s.frames = frames_;
  return s;
}

}  // namespace retreat::agent
