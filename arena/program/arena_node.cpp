#include "retreat/arena/arena_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <thread>

#include "retreat/core/seed.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::arena {

using namespace std::chrono_literals;

/// What only some ticks touch: the endpoints, the record, a real robot's poses. (What every
/// tick touches is in TickState.)
struct ArenaNode::Robot {
  std::uint32_t id;
  AgentRecord record;
  robot::Endpoints endpoints;  ///< the same endpoints a real robot's link uses
  /// With run.plans: the agent's plan reader (its last plan is in TickState).
  std::optional<transport::Reader<wire::Decision>> plans = std::nullopt;
  double frame_time = 0.0;         ///< the time of the last frame sent, which a plan must echo
  /// A real robot (arena.external_robots): its tracked poses, and what the arena knows of them.
  struct External {
    transport::Reader<wire::Poses> poses;
    bool has_pose = false;
    bool frozen = false;
    double robot_time = 0.0;  ///< the robot's clock at its last accepted pose [s]
    double x = 0.0;
    double y = 0.0;
    double seen_at = 0.0;     ///< arena time of its last accepted pose [s]
  };
  std::unique_ptr<External> external;
};

namespace {

wire::Phase to_wire(physics::Phase p) { return static_cast<wire::Phase>(static_cast<std::uint8_t>(p)); }

/// Lockstep waits past run.agent_timeout for agents still matched: reported on stderr this
/// many times, then only counted (summary.json's slow_answers).
constexpr std::uint64_t slow_answers_reported = 10;

}  // namespace

wire::ArenaTelemetry telemetry_message(const physics::Telemetry& t, std::uint32_t lost_agents,
                                       double ticks_per_second) {
  wire::ArenaTelemetry m;
  m.arena_id = 0;
  m.tick = t.tick;
  m.time = t.time;
  m.inside = t.inside;
  m.waiting = t.waiting;
  m.retreating = t.retreating;
  m.departed = t.departed;
  m.lost_agents = lost_agents;
  m.true_density = t.true_density;
  m.deliveries = t.deliveries;
  m.ticks_per_second = ticks_per_second;
  return m;
}

ArenaNode::ArenaNode(const scenario::Scenario& scenario, transport::Transport& transport,
                     RunRecorder* recorder)
    : scenario_(scenario),
      transport_(transport),
      recorder_(recorder),
      world_(physics::make_world(scenario.arena)),
      sensor_{scenario.arena.missed_onsets, scenario.arena.false_onsets, scenario.arena.tick_dt},
      telemetry_(transport.create_writer<wire::ArenaTelemetry>(
          {wire::arena_telemetry_topic(scenario.dds.prefix),
           transport::QosIntent::state().kept_for_recorders(scenario.run.recorders)})),
      poses_(transport.create_writer<wire::Poses>(
          {wire::poses_topic(scenario.dds.prefix),
           transport::QosIntent::state().kept_for_recorders(scenario.run.recorders)})) {
  for (const auto& f : world_->frames()) robot(f.id);
}

ArenaNode::~ArenaNode() = default;

ArenaNode::Robot& ArenaNode::robot(std::uint32_t id) {
  // Ids are dense (the world's 0 .. robot_count()−1): every id up to this one gets its endpoints.
  while (robots_.size() <= id) {
    const auto next = static_cast<std::uint32_t>(robots_.size());
    ticks_.emplace_back();
    const auto& prefix = scenario_.dds.prefix;
    robots_.push_back(std::make_unique<Robot>(Robot{
        .id = next,
        .record = AgentRecord{next},
        .endpoints = robot::Endpoints(transport_, prefix, next),
        .external = nullptr}));
    if (scenario_.run.plans) robots_.back()->plans.emplace(robot::plan_reader(transport_, prefix, next));
    if (next < scenario_.arena.external_robots) {
      robots_.back()->external = std::make_unique<Robot::External>(
          Robot::External{robot::tracked_pose_reader(transport_, prefix, next)});
    }
  }
  return *robots_[id];
}

ArenaNode::TickState& ArenaNode::tick_state(std::uint32_t id) {
  if (id >= ticks_.size()) robot(id);
  return ticks_[id];
}

std::uint32_t ArenaNode::wait_for_agents(std::chrono::nanoseconds timeout, const KeepGoing& keep_going) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  // A resumed arena (replay) may have departed robots: their agents have exited, having retreated.
  auto departed = [&](const Robot& r) { return ticks_[r.id].phase == wire::Phase::departed; };
  auto matched = [&](const Robot& r) {
    return departed(r) ? r.record.retreated
                       : r.endpoints.matched() && (!r.plans || r.plans->matched_count() > 0) &&
                             (!r.external || r.external->has_pose);
  };
  // run.recorders: every robot's frames and the telemetry and poses must also reach that many
  // recorders before tick 0 (the agents wait likewise for their own writers), so that a
  // recording holds every sample of the run.
  const std::uint32_t wanted = scenario_.run.recorders;
  std::set<std::string> recorders;
  bool recorders_ready = wanted == 0;
  for (;;) {
    take_external_poses();
    if (wanted > 0) {
      recorders = transport::participants_announcing(transport_, wire::recorder_user_data);
      recorders_ready = recorders.size() >= wanted &&
                        transport::matched_with_all(telemetry_.matched(), recorders) &&
                        transport::matched_with_all(poses_.matched(), recorders);
    }
    std::uint32_t n = 0;
    for (const auto& r : robots_) {
      const bool recorded =
          wanted == 0 || transport::matched_with_all(r->endpoints.frames.matched(), recorders);
      n += (matched(*r) && recorded) || departed(*r) ? 1 : 0;
    }
    if ((n == robots_.size() && recorders_ready) || std::chrono::steady_clock::now() >= deadline ||
        !keep_going()) {
      break;
    }
    std::this_thread::sleep_for(10ms);
  }
  if (!recorders_ready) {
    std::fprintf(stderr,
                 "retreat-arena: run.recorders = %u, but %zu seen and not every topic matched "
                 "within run.startup_timeout; a recording may miss the first samples\n",
                 wanted, recorders.size());
  }
  agents_started_ = 0;
  for (auto& r : robots_) {
    r->record.matched = matched(*r);
    if (r->record.matched) {
      ++agents_started_;
    } else if (!departed(*r)) {
      declare_lost(*r, 0.0);  // never came: the robot works without a retreat layer
    }
  }
  for (auto& r : robots_) {
    if (r->external && !r->external->has_pose && !departed(*r) && world_->lose_external(r->id)) {
      ++external_.lost;  // a real robot that never reported a pose cannot be in the arena
      std::fprintf(stderr, "retreat-arena: real robot %u sent no pose before the start: lost\n", r->id);
    }
  }
  started_ = std::chrono::steady_clock::now();
  return agents_started_;
}

void ArenaNode::take_external_poses() {
  const auto& p = scenario_.arena;
  if (p.external_robots == 0) return;
  const double now = world_->telemetry().time;
  for (std::uint32_t id = 0; id < p.external_robots && id < robots_.size(); ++id) {
    auto& r = robots_[id];
    auto& e = *r->external;
    e.poses.take(taken_poses_);
    for (const auto& sample : taken_poses_) {
      const auto& pose = sample.robots.front();  // validation: exactly one, this robot's
      if (e.has_pose && sample.time < e.robot_time) {
        ++external_.poses_clock_back;
        continue;
      }
      const double moved = std::hypot(pose.x - e.x, pose.y - e.y);
      if (e.has_pose && moved > p.external_max_speed * (sample.time - e.robot_time) + p.robot_radius) {
        ++external_.poses_jumped;  // tracking glitch or a wrong robot: not a move it can make
        continue;
      }
      if (!world_->set_external_pose(r->id, pose.x, pose.y, pose.theta)) continue;  // not in D any more
      ++external_.poses_accepted;
      e.has_pose = true;
      e.frozen = false;
      e.robot_time = sample.time;
      e.x = pose.x;
      e.y = pose.y;
      e.seen_at = now;
    }
    if (!e.has_pose || ticks_[id].phase == wire::Phase::departed) continue;
    const double age = now - e.seen_at;
    if (age > p.external_lost_after) {
      if (world_->lose_external(r->id)) {
        ++external_.lost;
        std::fprintf(stderr, "retreat-arena: real robot %u: no pose for %.1f s: lost (it departs)\n", r->id, age);
      }
    } else if (age > p.external_frozen_after && !e.frozen) {
      e.frozen = true;
      ++external_.frozen;
      std::fprintf(stderr, "retreat-arena: real robot %u: no pose for %.1f s: frozen where last seen\n", r->id, age);
    }
  }
}

ExternalCounters ArenaNode::external_counters() const {
  ExternalCounters c = external_;
  for (const auto& r : robots_) {
    if (r->external) c.poses_invalid += r->external->poses.stats().dropped_total();
  }
  return c;
}

void ArenaNode::publish_tick() {
  sent_.clear();
  // The run's last tick is sent to every robot, its plan in force or not: its agent then acts on
  // the ticks the plan covered, and publishes their statuses, before the run ends.
  const bool last = settle_plans_at_end_ && duration_reached();
  const bool plans = scenario_.run.plans;
  for (const auto& f : world_->frames()) {
    // A covered tick touches this robot's TickState only: with 10⁵ robots, reaching its Robot
    // too (endpoints, record) every tick cost more than the agents' own work.
    auto& t = tick_state(f.id);
    t.phase = to_wire(f.phase);
    t.sensed_onsets = sensor_.perfect()
                          ? f.new_onsets
                          : sensor_.sense(f.new_onsets, seed_for(scenario_.seed, f.id, Stream::sensor), f.tick);
    t.answered = false;
    if (!t.commanded) t.retreat = false;
    t.expecting = !t.lost && f.phase != physics::Phase::departed;
    // A lost agent gets no more frames: a reliable writer would otherwise queue them for a
    // reader that never acknowledges, and block once its history is full.
    if (t.lost) continue;
    if (plans) {
      if (!last && f.tick <= t.plan_through && t.sensed_onsets == 0 && t.phase == t.plan_phase) {
        // Covered: the agent decided this tick already, in the plan it answered with.
        ++counters_.planned;
        if (t.expecting) act_on_answer(f.id, plan_decision(t, f.tick));
        t.answered = true;
        continue;
      }
      t.plan_through = -1;  // the input changed, or the plan ended: the agent answers this frame
    }
    auto& r = *robots_[f.id];
    if (plans) r.frame_time = f.time;
    const wire::ProximityFrame frame{f.id, f.tick, f.time, t.phase, f.in_contact, t.sensed_onsets};
    if (r.endpoints.frames.write(frame) != transport::WriteResult::ok) {
      if (t.expecting) {
        // The agent's reader has stopped acknowledging: treat it like a silent agent.
        t.expecting = false;
        declare_lost(r, f.time);
      }
      continue;
    }
    sent_.push_back(f.id);
  }
  publish_observations();
}

void ArenaNode::publish_observations() {
  const auto t = world_->telemetry();
  const auto slot = static_cast<std::int64_t>(std::floor(t.time / scenario_.run.telemetry_period + 1e-9));
  if (slot == last_published_slot_) return;
  last_published_slot_ = slot;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  telemetry_.write(telemetry_message(t, agents_lost(), wall > 0 ? static_cast<double>(t.tick) / wall : 0.0));
  const auto p = world_->poses();
  wire::Poses poses;
  poses.arena_id = 0;
  poses.tick = p.tick;
  poses.time = p.time;
  for (const auto& r : p.robots) {
    poses.robots.push_back({r.id, static_cast<float>(r.x), static_cast<float>(r.y),
                            static_cast<float>(r.theta), to_wire(r.phase), r.loaded});
  }
  for (const auto& q : p.pickups) poses.pickups.push_back({static_cast<float>(q.x()), static_cast<float>(q.y())});
  for (const auto& q : p.dropoffs) poses.dropoffs.push_back({static_cast<float>(q.x()), static_cast<float>(q.y())});
  poses_.write(poses);
}

void ArenaNode::act_on_answer(std::uint32_t id, bool retreat) {
  if (!retreat) return;
  if (auto& record = robots_[id]->record; !record.retreated) {
    record.retreated = true;
    record.retreat_at = world_->telemetry().time;
  }
  ticks_[id].retreat = true;
}

bool ArenaNode::plan_decision(const TickState& t, std::int64_t tick) {
  // The plan's own decision if it ends at this tick; before its end, no retreat (an agent that
  // had decided is commanded already, and its retreat stays).
  return tick == t.plan_through && t.plan_retreat;
}

bool ArenaNode::settled_plan(const Robot& r, const wire::Decision& p, std::int64_t current) {
  if (ticks_[r.id].phase == wire::Phase::departed) return true;  // the answer to its last frame: nothing to do
  if (p.robot_id >= world_->robot_count()) {
    ++counters_.unknown_robot;
  } else if (const auto verdict = robot::judge_plan(p, current, r.frame_time);
             verdict == robot::DecisionVerdict::future) {
    ++counters_.future;
  } else if (verdict == robot::DecisionVerdict::stale || r.record.lost) {
    ++counters_.stale;  // answers a frame that is settled, or came from a lost agent
  } else {
    return false;
  }
  return true;
}

void ArenaNode::take_plans(Robot& r, std::int64_t current) {
  r.plans->take(taken_);
  auto& t = ticks_[r.id];
  for (const auto& p : taken_) {
    if (settled_plan(r, p, current)) continue;
    ++counters_.received;
    t.answered = true;
    t.plan_through = p.tick;
    t.plan_retreat = p.retreat;
    t.plan_phase = t.phase;
    act_on_answer(r.id, plan_decision(t, current));
  }
}

void ArenaNode::take_decisions(Robot& r, std::int64_t current) {
  if (r.plans) {
    take_plans(r, current);
    return;
  }
  const bool lockstep = scenario_.run.mode == scenario::RunMode::lockstep;
  r.endpoints.decisions.take(taken_);
  auto& t = ticks_[r.id];
  for (const auto& d : taken_) {
    if (t.phase == wire::Phase::departed) continue;  // the answer to its last frame: nothing to do
    if (d.robot_id >= world_->robot_count()) {
      ++counters_.unknown_robot;
    } else if (const auto verdict = robot::judge(d, current, lockstep); verdict == robot::DecisionVerdict::future) {
      ++counters_.future;
    } else if (verdict == robot::DecisionVerdict::stale || (lockstep && r.record.lost)) {
      ++counters_.stale;  // lockstep answers only count for the tick they answer
    } else {
      ++counters_.received;
      if (d.tick == current) t.answered = true;
      act_on_answer(r.id, d.retreat);
    }
  }
}

bool ArenaNode::all_answered() const {
  return std::none_of(ticks_.begin(), ticks_.end(), [](const TickState& t) { return owes_answer(t); });
}

bool ArenaNode::collect_available() {
  // Once per call, not per robot.
  const auto current = tick();
  bool all = true;
  if (scenario_.run.plans) {
    // Only a robot sent a frame this tick owes an answer: the others' plans cover the tick, and
    // whatever else their readers hold answers a settled frame (it is judged when the robot is
    // next sent a frame, or by finish()). A tick then costs the robots whose input changed.
    for (const auto id : sent_) {
      take_plans(*robots_[id], current);
      all = all && !owes_answer(ticks_[id]);
    }
    return all;
  }
  for (auto& r : robots_) {
    take_decisions(*r, current);
    all = all && !owes_answer(ticks_[r->id]);
  }
  return all;
}

bool ArenaNode::collect_lockstep(const KeepGoing& keep_going) {
  using Duration = std::chrono::steady_clock::duration;
  const auto wall = [](double seconds) {
    return std::chrono::duration_cast<Duration>(std::chrono::duration<double>(seconds));
  };
  const auto start = std::chrono::steady_clock::now();
  // Silent past run.agent_timeout: lost if its agent is gone from discovery, else waited for
  // (a loaded machine is slow, not dead) until run.agent_hang_timeout.
  const auto deadline = start + wall(scenario_.run.agent_timeout);
  const auto hang_deadline = start + wall(scenario_.run.agent_hang_timeout);
  bool waited = false;
  auto next_resend = start + robot::resend_interval;
  for (;;) {
    if (collect_available()) return true;
    if (!keep_going()) return false;
    if (std::chrono::steady_clock::now() >= next_resend) {
      // A frame (or its answer) written while the two sides were still discovering each other
      // may never arrive: volatile readers do not get samples written before they matched.
      // Re-send the frame; the agent answers a repeated tick with the decision it recorded.
      resend_unanswered();
      next_resend += robot::resend_interval;
    }
    if (const auto now = std::chrono::steady_clock::now(); now >= deadline) {
      bool waiting = false;
      for (auto& r : robots_) {
        if (!owes_answer(ticks_[r->id])) continue;
        if (now < hang_deadline && agent_present(*r)) {
          waiting = true;
          if (!waited) ++counters_.slow_answers;
          continue;
        }
        declare_lost(*r, world_->telemetry().time);
      }
      if (waiting && !waited) {
        waited = true;
        if (counters_.slow_answers <= slow_answers_reported) {
          std::fprintf(stderr,
                       "retreat-arena: tick %lld: an agent silent for run.agent_timeout = %g s is still matched: "
                       "waiting up to run.agent_hang_timeout = %g s%s\n",
                       static_cast<long long>(tick()), scenario_.run.agent_timeout, scenario_.run.agent_hang_timeout,
                       counters_.slow_answers == slow_answers_reported ? " (further waits are counted only)" : "");
        }
      }
      if (!waiting) return true;
    }
    transport_.wait(5ms);
  }
}

bool ArenaNode::agent_present(const Robot& r) {
  return r.endpoints.decisions.matched_count() > 0 || (r.plans && r.plans->matched_count() > 0);
}

void ArenaNode::resend_unanswered() {
  for (const auto& f : world_->frames()) {
    auto& r = robot(f.id);
    const auto& t = ticks_[f.id];
    if (!owes_answer(t)) continue;
    r.endpoints.frames.write({f.id, f.tick, f.time, t.phase, f.in_contact, t.sensed_onsets});
    ++counters_.resent_frames;
  }
}

void ArenaNode::step() {
  take_external_poses();
  advance(nullptr);
}

void ArenaNode::replay(std::int64_t ticks, const RetreatJournal& journal) {
  while (tick() < ticks && !finished()) advance(&journal);
  for (const auto& f : world_->frames()) tick_state(f.id).phase = to_wire(f.phase);
  resumed_at_tick_ = tick();
}

void ArenaNode::advance(const RetreatJournal* journal) {
  const auto current = tick();
  for (const auto& f : world_->frames()) {
    auto& t = tick_state(f.id);
    if (journal != nullptr) {
      // What publish_tick and take_decisions did live at this tick, from the journal.
      t.phase = to_wire(f.phase);
      const auto [first, last] = journal->equal_range(current);
      const bool journalled = std::any_of(first, last, [&](const auto& e) { return e.second == f.id; });
      t.retreat = t.commanded || journalled;
      if (auto& record = robots_[f.id]->record;
          journalled && !record.retreated && t.phase != wire::Phase::departed) {
        record.retreated = true;
        record.retreat_at = world_->telemetry().time;
      }
    } else if (t.retreat && !t.commanded && recorder_ != nullptr) {
      recorder_->record_retreat(current, f.id);
    }
    const bool retreat = t.retreat && f.phase == physics::Phase::inside;
    hash_.add(current, f.id, static_cast<std::uint8_t>(f.phase), t.retreat);
    if (recorder_ != nullptr) recorder_->record_state(current, f.id, static_cast<std::uint8_t>(f.phase), t.retreat);
    if (retreat && !t.commanded) {
      if (world_->command_retreat(f.id) == physics::CommandVerdict::accepted) ++counters_.applied;
      t.commanded = true;
    }
  }
  if (recorder_ != nullptr) recorder_->record_link(current, hash_.link());
  world_->step_tick();
  // Endless queue: new robots appear (ids are dense: the last one gives every one before it).
  if (const auto count = world_->robot_count(); count > 0) robot(static_cast<std::uint32_t>(count - 1));
  if (recorder_ != nullptr) {
    recorder_->record_tick(world_->telemetry(), journal == nullptr);
    if (scenario_.arena.record_encounters) {
      auto contacts = world_->take_contact_records();  // replayed ones are on disk already
      if (journal == nullptr) recorder_->record_contacts(contacts);
    }
  }
}

bool ArenaNode::duration_reached() const {
  return world_->telemetry().time >= scenario_.run.duration - 1e-9;
}

bool ArenaNode::finished() const {
  if (duration_reached()) return true;
  const auto t = world_->telemetry();
  return t.inside == 0 && t.retreating == 0 && t.waiting == 0 && t.tick > 0;
}

DecisionCounters ArenaNode::decisions() const {
  DecisionCounters c = counters_;
  c.invalid = 0;
  for (const auto& r : robots_) {
    c.invalid += r->endpoints.decisions.stats().dropped_total();
    if (r->plans) c.invalid += r->plans->stats().dropped_total();
  }
  return c;
}

std::int64_t ArenaNode::tick() const { return world_->telemetry().tick; }

std::uint32_t ArenaNode::agents_lost() const { return agents_lost_; }

void ArenaNode::declare_lost(Robot& r, double at) {
  r.record.lost = true;
  r.record.lost_at = at;
  ticks_[r.id].lost = true;
  if (r.record.matched) ++agents_lost_;  // an agent that never came is not counted lost
}

void ArenaNode::count_leftover_plans() {
  const auto current = tick();
  for (auto& r : robots_) {
    if (!r->plans) continue;
    r->plans->take(taken_);
    for (const auto& p : taken_) {
      if (!settled_plan(*r, p, current)) ++counters_.stale;  // a repeat of the plan in force: settled too
    }
  }
}

bool ArenaNode::flush(std::chrono::nanoseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  const auto left = [&] { return transport::time_left(deadline); };
  bool all = telemetry_.wait_for_acknowledgments(left()) && poses_.wait_for_acknowledgments(left());
  for (auto& r : robots_) all = r->endpoints.frames.wait_for_acknowledgments(left()) && all;
  return all;
}

RunSummary ArenaNode::finish(double wall_seconds) {
  if (scenario_.run.plans) count_leftover_plans();
  publish_observations();
  RunSummary s;
  s.ticks = tick();
  s.wall_seconds = wall_seconds;
  s.agents_started = agents_started_;
  s.agents_lost = agents_lost();
  const auto counters = decisions();
  s.decisions_dropped = counters.stale + counters.future + counters.unknown_robot + counters.invalid;
  s.frames_resent = counters_.resent_frames;
  s.slow_answers = counters_.slow_answers;
  s.decisions_received = counters_.received;
  s.decisions_planned = counters_.planned;
  s.resumed_at_tick = resumed_at_tick_;
  s.trajectory_sha256 = hash_.finish();
  s.dds = std::string(transport_.vendor());
  s.external = external_counters();
  if (recorder_ != nullptr) {
    std::vector<AgentRecord> agents;
    for (const auto& r : robots_) agents.push_back(r->record);
    recorder_->finish(*world_, agents, s);
  }
  return s;
}

}  // namespace retreat::arena
