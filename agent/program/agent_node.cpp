#include "retreat/agent/agent_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <thread>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/scenario/params.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::agent {
namespace {

/// How often the agent lists the readers of its decisions (a restarted arena takes longer than
/// this to rebuild its world and match again; listing them builds a vector of GUID strings, too
/// much to do for every agent of a large swarm several times a second).
constexpr std::chrono::milliseconds reader_check_period{1000};
/// ... and at most every this many spins (one spin per frame or wait).
constexpr std::uint64_t reader_check_spins = 16;

Observation to_observation(const wire::ProximityFrame& f) {
  return {f.tick, f.time, static_cast<RobotPhase>(f.phase), f.in_contact, f.new_onsets, f.robot_id};
}

}  // namespace

std::string agent_user_data(std::uint32_t robot_id) {
  return "retreat:agent:robot=" + std::to_string(robot_id);
}

AgentNode::AgentNode(const scenario::Scenario& scenario, std::uint32_t robot_id,
                     transport::Transport& transport, const std::string& journal_path)
    : transport_(transport),
      robot_id_(robot_id),
      status_period_(scenario.run.status_period),
      agent_(robot_id, scenario.model, scenario.agent, make_controller(scenario.agent.controller),
             seed_for(scenario.seed, robot_id, Stream::agent_decision)),
      frames_topic_{wire::proximity_topic(scenario.dds.prefix, robot_id), transport::QosIntent::control()},
      recorders_(scenario.run.recorders),
      recorders_deadline_(std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(scenario.run.startup_timeout))),
      // Without recorders the frames reader comes first, as it always has; with them, once the
      // recorders read our writers (open_frames).
      frames_(recorders_ == 0 ? std::make_optional(transport.create_reader<wire::ProximityFrame>(frames_topic_))
                              : std::nullopt),
      decisions_(transport.create_writer<wire::Decision>(
          {wire::decision_topic(scenario.dds.prefix, robot_id),
           transport::QosIntent::answers().kept_for_recorders(recorders_)})),
      clock_(scenario::frame_clock(scenario)),
      plan_horizon_(scenario.run.plan_horizon),
      statuses_(transport.create_writer<wire::AgentStatus>(
          {wire::agent_status_topic(scenario.dds.prefix),
           transport::QosIntent::state().kept_for_recorders(recorders_)})) {
  if (scenario.run.plans) {
    plans_.emplace(transport.create_writer<wire::Decision>(
        {wire::plan_topic(scenario.dds.prefix, robot_id),
         transport::QosIntent::answers().kept_for_recorders(recorders_)}));
  }
  open_frames();
  if (journal_path.empty()) return;
  journal_ = std::make_unique<FrameJournal>(journal_path, journal_header(scenario, robot_id), robot_id);
  for (const auto& f : journal_->recovered()) recover(f);
  if (last_frame_) {
    // A re-sent last frame gets the answer the dead process gave (or, with plans, one that
    // decides the same: every plan from the same state agrees on the ticks it covers).
    last_decision_ = answer(*last_frame_, FrameResult{FrameVerdict::accepted, false, agent_.retreating()});
  }
}

void AgentNode::recover(const wire::ProximityFrame& frame) {
  ++counters_.frames_recovered;
  const auto result = agent_.on_frame(to_observation(frame));
  if (result.verdict != FrameVerdict::accepted) return;  // cannot happen for what handle() wrote
  last_frame_ = frame;
  last_answered_tick_ = frame.tick;
  last_retreating_ = result.retreating;
  departed_ = departed_ || frame.phase == wire::Phase::departed;
}

bool AgentNode::arena_seen() {
  if (arena_seen_) return true;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_arena_check_) return false;
  next_arena_check_ = now + std::chrono::seconds(1);
  arena_seen_ = counters_.frames_received > 0 || (frames_ && frames_->matched_count() > 0) || decisions_.matched_count() > 0;
  if (!arena_seen_) {
    const auto participants = transport_.participants();
    arena_seen_ = std::any_of(participants.begin(), participants.end(), [](const transport::ParticipantInfo& p) {
      return p.user_data.rfind(wire::arena_user_data, 0) == 0;
    });
  }
  return arena_seen_;
}

bool AgentNode::open_frames() {
  if (frames_) return true;
  // run.recorders: the frames reader opens once the recorders read every writer of ours, so that
  // the arena, which waits for it before tick 0, starts only when nothing we write can be missed.
  if (!recorders_matched()) {
    if (std::chrono::steady_clock::now() < recorders_deadline_) return false;
    std::fprintf(stderr, "retreat-agent robot %u: run.recorders = %u not matched within "
                 "run.startup_timeout; a recording may miss this robot's first samples\n",
                 robot_id_, recorders_);
  }
  frames_.emplace(transport_.create_reader<wire::ProximityFrame>(frames_topic_));
  return true;
}

bool AgentNode::recorders_matched() const {
  if (recorders_ == 0) return true;
  const auto recorders = transport::participants_announcing(transport_, wire::recorder_user_data);
  return recorders.size() >= recorders_ && transport::matched_with_all(decisions_.matched(), recorders) &&
         transport::matched_with_all(statuses_.matched(), recorders) &&
         (!plans_ || transport::matched_with_all(plans_->matched(), recorders));
}

void AgentNode::spin_once(std::chrono::nanoseconds timeout) {
  // One buffer per thread rather than one per agent: a swarm in one process spins every agent
  // on one thread, and one buffer in the cache beats a cold one per agent. handle() never spins.
  thread_local std::vector<wire::ProximityFrame> taken;
  if (!open_frames()) {
    std::this_thread::sleep_for(std::min<std::chrono::nanoseconds>(timeout, std::chrono::milliseconds(10)));
    return;
  }
  frames_->take(taken);
  if (taken.empty()) {
    transport_.wait(timeout);  // our reader is the transport's only one
    frames_->take(taken);
  }
  for (const auto& f : taken) handle(f);
  counters_.frames_dropped = frames_->stats().dropped_total() + agent_.frames().dropped();
  watch_decision_readers();
}

void AgentNode::watch_decision_readers() {
  // The clock is read every reader_check_spins spins only: a swarm in one process spins every
  // agent every tick, and a clock read per agent per tick would cost as much as the world.
  if (spins_++ % reader_check_spins != 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (now < next_reader_check_) return;
  next_reader_check_ = now + reader_check_period;
  for (const auto& reader : decisions_.matched()) {
    if (!decision_readers_.insert(reader.participant_guid).second) continue;
    // This reader's participant only, not the list of all: in one process, that list is the swarm.
    const auto participant = transport_.participant(reader.participant_guid);
    if (participant && participant->user_data == wire::recorder_user_data) continue;  // a recorder, not an arena
    ++counters_.arena_incarnations;
    if (counters_.arena_incarnations == 1) continue;
    // Nothing to undo: the tick order makes the new arena's first frame a duplicate or the next
    // tick, and the dead one stays matched until its lease expires, holding at most
    // QosIntent::answers_depth of our decisions (a new writer would match it all the same).
    std::fprintf(stderr,
                 "retreat-agent robot %u: a new arena incarnation reads our decisions (participant %s, "
                 "incarnation %u); the previous one is left to its lease\n",
                 robot_id_, reader.participant_guid.c_str(), counters_.arena_incarnations);
  }
}

void AgentNode::handle(const wire::ProximityFrame& frame) {
  ++counters_.frames_received;
  if (plans_) act_on_covered(frame.tick);
  const auto result = agent_.on_frame(to_observation(frame));
  if (result.verdict == FrameVerdict::duplicate_tick && last_decision_ && last_answered_tick_ == frame.tick) {
    // A lockstep re-send: the arena has not seen our answer (it may have been written before the
    // arena's reader matched our writer). Answer again with the recorded answer; the
    // algorithm does not see the frame twice (it was counted as a duplicate).
    answer_writer().write(*last_decision_);
    return;
  }
  if (result.verdict != FrameVerdict::accepted) return;
  // Journalled before it is answered: every answer the arena can have seen survives a restart.
  after_frame(frame, result);
  // Every accepted frame is answered: with this tick's decision, or with a plan (lockstep waits).
  last_decision_ = answer(frame, result);
  last_answered_tick_ = frame.tick;
  if (answer_writer().write(*last_decision_) == transport::WriteResult::ok) {
    ++counters_.decisions_sent;
  } else {
    ++counters_.write_failures;
  }
}

void AgentNode::act_on_covered(std::int64_t tick) {
  if (!last_frame_ || tick <= last_frame_->tick + 1) return;
  wire::ProximityFrame covered = *last_frame_;
  covered.in_contact = false;
  covered.new_onsets = 0;
  // The covered frames that decide nothing and publish nothing (no status period starts) are
  // taken in one go (RetreatAgent::take_quiet_frames): the agent ends exactly as frame by frame.
  // Not with a journal, which keeps every frame, nor for a departed robot, whose every frame
  // publishes a status.
  const bool in_one_go = !journal_ && covered.phase != wire::Phase::departed;
  const RobotPhase phase = to_observation(covered).phase;
  for (std::int64_t t = last_frame_->tick + 1; t < tick; ++t) {
    // Asked first, so that an agent deciding every frame pays one comparison, not a bisection.
    if (in_one_go && agent_.quiet_through(clock_, phase, t) == t) {
      const std::int64_t quiet = agent_.take_quiet_frames(clock_, phase, last_of_status_slot(t, tick - 1));
      if (quiet >= t) {
        counters_.frames_covered += static_cast<std::uint64_t>(quiet - t + 1);
        covered.tick = quiet;
        covered.time = clock_.time(quiet);
        last_frame_ = covered;
        t = quiet;
        continue;
      }
    }
    covered.tick = t;
    covered.time = clock_.time(t);
    const auto result = agent_.on_frame(to_observation(covered));
    if (result.verdict != FrameVerdict::accepted) return;
    ++counters_.frames_covered;
    after_frame(covered, result);
  }
}

std::int64_t AgentNode::status_slot(double time) const {
  return static_cast<std::int64_t>(std::floor(time / status_period_));
}

std::int64_t AgentNode::last_of_status_slot(std::int64_t from, std::int64_t to) const {
  // Frame times never go back on the clock, nor do their slots: a bisection finds the last.
  const auto same = [&](std::int64_t t) { return status_slot(clock_.time(t)) == last_status_slot_; };
  return last_tick_where(from, to, same);
}

void AgentNode::after_frame(const wire::ProximityFrame& frame, const FrameResult& result) {
  if (journal_) journal_->append(frame);
  last_frame_ = frame;
  const auto slot = status_slot(frame.time);
  const bool phase_end = frame.phase == wire::Phase::departed;
  if (slot != last_status_slot_ || result.retreating != last_retreating_ || phase_end) {
    last_status_slot_ = slot;
    last_retreating_ = result.retreating;
    publish_status(frame.tick, frame.time);
  }
  departed_ = departed_ || phase_end;
}

wire::Decision AgentNode::answer(const wire::ProximityFrame& frame, const FrameResult& result) {
  if (!plans_ || result.retreat_now) return {robot_id_, frame.tick, frame.time, result.retreating};
  // A plan needs the arena's frames on our frame clock, bit for bit; a frame off it (a scenario
  // that differs from the arena's) gets a plan that covers nothing but its own tick.
  if (frame.time != clock_.time(frame.tick)) {
    if (!clock_warned_) {
      clock_warned_ = true;
      std::fprintf(stderr,
                   "retreat-agent robot %u: frame %lld at %.17g s is not on the frame clock (%.17g s): "
                   "answering without look-ahead (does the arena run another scenario?)\n",
                   robot_id_, static_cast<long long>(frame.tick), frame.time, clock_.time(frame.tick));
    }
    return {robot_id_, frame.tick, frame.time, result.retreating};
  }
  const Plan plan = agent_.plan(clock_, plan_horizon_);
  return {robot_id_, plan.through_tick, frame.time, result.retreating || plan.retreat_tick.has_value()};
}

void AgentNode::publish_status(std::int64_t tick, double time) {
  const auto s = agent_.status();
  wire::AgentStatus status;
  status.robot_id = robot_id_;
  status.tick = tick;
  status.time = time;
  status.deciding = s.deciding;
  status.retreating = s.retreating;
  status.onsets_in_window = static_cast<std::uint32_t>(s.onsets_in_window);
  status.lambda_hat = s.lambda_hat;
  status.epsilon = std::isfinite(s.epsilon) && s.epsilon >= 0.0 ? s.epsilon : 0.0;
  status.frames_dropped = (frames_ ? frames_->stats().dropped_total() : 0) + s.frames.dropped();
  if (statuses_.write(status) == transport::WriteResult::ok) {
    ++counters_.statuses_sent;
  } else {
    ++counters_.write_failures;
  }
}

void AgentNode::flush(std::chrono::nanoseconds timeout) {
  // One deadline for every writer, plans included: a recorder that has not yet acknowledged a
  // robot's last plan would otherwise lose the answer to its last frame when the agent exits.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  decisions_.wait_for_acknowledgments(transport::time_left(deadline));
  if (plans_) plans_->wait_for_acknowledgments(transport::time_left(deadline));
  statuses_.wait_for_acknowledgments(transport::time_left(deadline));
}

}  // namespace retreat::agent
