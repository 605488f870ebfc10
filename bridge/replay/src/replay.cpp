#include "retreat/replay/replay.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>

#include "retreat/scenario/scenario.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::replay {
namespace {

using Clock = std::chrono::steady_clock;

/// The first frame of each tick, in tick order (a lockstep re-send repeats a tick).
std::vector<const Recorded<wire::ProximityFrame>*> distinct_frames(const RecordedRobot& robot) {
  std::map<std::int64_t, const Recorded<wire::ProximityFrame>*> by_tick;
  for (const auto& f : robot.frames) by_tick.try_emplace(f.sample.tick, &f);
  std::vector<const Recorded<wire::ProximityFrame>*> out;
  out.reserve(by_tick.size());
  for (const auto& [tick, f] : by_tick) out.push_back(f);
  return out;
}

/// Whether @p answer answers @p frame: a decision for its tick; a plan from its time on.
bool answers(const wire::Decision& answer, const wire::ProximityFrame& frame, bool plans) {
  if (answer.robot_id != frame.robot_id) return false;
  if (plans) return answer.time == frame.time && answer.tick >= frame.tick;
  return answer.tick == frame.tick;
}

/// The tick a sequence of answers retreats at (sticky): a decision's tick, a plan's last tick.
std::int64_t retreat_tick(const std::vector<Recorded<wire::Decision>>& answers) {
  std::int64_t at = -1;
  for (const auto& a : answers) {
    if (a.sample.retreat && (at < 0 || a.sample.tick < at)) at = a.sample.tick;
  }
  return at;
}

std::string answer_text(const wire::Decision& d) {
  return std::string(d.retreat ? "retreat" : "stay") + " (tick " + std::to_string(d.tick) + ")";
}

bool same_decision(const wire::Decision& a, const wire::Decision& b) {
  return a.robot_id == b.robot_id && a.tick == b.tick && a.time == b.time && a.retreat == b.retreat;
}

}  // namespace

scenario::Scenario agent_scenario(const Recording& recording, const ReplayOptions& options) {
  auto s = recording.scenario;
  s.run.recorders = 0;
  if (options.redecide()) {
    if (!options.controller.empty()) s.agent.controller = options.controller;
    for (const auto& o : options.agent_overrides) {
      if (o.rfind("agent.", 0) != 0) {
        throw scenario::ConfigError("--set '" + o + "': a replay changes the agents' parameters only (agent.key=value)");
      }
      scenario::apply_override(s, o);
    }
    s.run.plans = false;
    scenario::resolve(s);
    scenario::validate(s);
  }
  return s;
}

std::vector<RobotScript> make_scripts(const Recording& recording, const ReplayOptions& options) {
  std::vector<std::uint32_t> ids = options.robots;
  if (ids.empty()) {
    for (const auto& [id, robot] : recording.robots) {
      if (!robot.frames.empty()) ids.push_back(id);
    }
  }
  const bool redecide = options.redecide();
  const bool plans = recording.scenario.run.plans;
  const auto clock = scenario::frame_clock(recording.scenario);
  std::vector<RobotScript> out;
  for (const auto id : ids) {
    const auto it = recording.robots.find(id);
    if (it == recording.robots.end() || it->second.frames.empty()) {
      throw RecordingError("'" + recording.path + "': robot " + std::to_string(id) + " has no frames in it");
    }
    const auto& robot = it->second;
    const auto frames = distinct_frames(robot);
    RobotScript s;
    s.robot = id;
    s.recorded_retreat_tick = retreat_tick(robot.answers);
    if (!redecide) {
      // The first recorded answer to each frame: a decision by its tick, a plan by its frame's
      // time (checked with answers(), which also wants the plan to reach the frame's tick).
      std::map<std::int64_t, const wire::Decision*> by_tick;
      std::map<double, std::vector<const wire::Decision*>> by_time;
      for (const auto& a : robot.answers) {
        if (plans) by_time[a.sample.time].push_back(&a.sample);
        else by_tick.try_emplace(a.sample.tick, &a.sample);
      }
      for (const auto* f : frames) {
        s.frames.push_back(f->sample);
        s.due_ns.push_back(f->log_time - frames.front()->log_time);
        std::optional<wire::Decision> expected;
        if (plans) {
          if (const auto same_time = by_time.find(f->sample.time); same_time != by_time.end()) {
            for (const auto* a : same_time->second) {
              if (answers(*a, f->sample, true)) {
                expected = *a;
                break;
              }
            }
          }
        } else if (const auto same_tick = by_tick.find(f->sample.tick);
                   same_tick != by_tick.end() && answers(*same_tick->second, f->sample, false)) {
          expected = *same_tick->second;
        }
        s.expected.push_back(expected);
      }
    } else {
      // Every tick: the recorded frames, and between them (with plans) the ticks a plan covered.
      for (std::size_t i = 0; i < frames.size(); ++i) {
        const auto& f = frames[i]->sample;
        if (i > 0 && plans) {
          auto covered = frames[i - 1]->sample;
          covered.in_contact = false;
          covered.new_onsets = 0;
          for (auto t = covered.tick + 1; t < f.tick; ++t) {
            covered.tick = t;
            covered.time = clock.time(t);
            s.frames.push_back(covered);
          }
        }
        s.frames.push_back(f);
      }
      for (const auto& f : s.frames) {
        const bool retreat = s.recorded_retreat_tick >= 0 && f.tick >= s.recorded_retreat_tick;
        s.expected.push_back(wire::Decision{f.robot_id, f.tick, f.time, retreat});
        s.due_ns.push_back(0);
      }
    }
    out.push_back(std::move(s));
  }
  return out;
}

struct Driver::Robot {
  RobotScript script;
  transport::Writer<wire::ProximityFrame> frames;
  transport::Reader<wire::Decision> answers;
  std::size_t next = 0;                 ///< the frame to send next
  bool awaiting = false;                ///< frames[next] was sent, its answer not yet taken
  Clock::time_point sent_at{}, first_sent_at{};
  RobotOutcome outcome;
  bool done() const { return next >= script.frames.size() || !outcome.failure.empty(); }
};

Driver::Driver(transport::Transport& transport, const std::string& prefix, std::vector<RobotScript> scripts,
               bool plans, Pace pace, std::chrono::nanoseconds answer_timeout)
    : plans_(plans), pace_(pace), answer_timeout_(answer_timeout) {
  robots_.reserve(scripts.size());
  for (auto& script : scripts) {
    const auto id = script.robot;
    const auto answer_topic = plans ? wire::plan_topic(prefix, id) : wire::decision_topic(prefix, id);
    Robot r{.script = std::move(script),
            .frames = transport.create_writer<wire::ProximityFrame>(
                {wire::proximity_topic(prefix, id), transport::QosIntent::control()}),
            .answers = transport.create_reader<wire::Decision>({answer_topic, transport::QosIntent::control()}),
            .outcome = {}};
    r.outcome.robot = id;
    r.outcome.frames = r.script.frames.size();
    r.outcome.recorded_retreat_tick = r.script.recorded_retreat_tick;
    robots_.push_back(std::move(r));
  }
}

Driver::~Driver() = default;
Driver::Driver(Driver&&) noexcept = default;

bool Driver::matched() const {
  return std::all_of(robots_.begin(), robots_.end(),
                     [](const Robot& r) { return r.frames.matched_count() > 0 && r.answers.matched_count() > 0; });
}

bool Driver::step(Clock::time_point now) {
  if (!started_) started_ = now;
  bool any = false;
  for (auto& r : robots_) {
    if (r.done()) continue;
    any = true;
    if (r.awaiting) {
      r.answers.take(taken_);
      const auto& frame = r.script.frames[r.next];
      for (const auto& a : taken_) {
        if (!r.awaiting || !answers(a, frame, plans_)) continue;  // a repeat of an earlier answer
        r.awaiting = false;
        ++r.outcome.answered;
        if (a.retreat && r.outcome.replayed_retreat_tick < 0) r.outcome.replayed_retreat_tick = a.tick;
        const auto& expected = r.script.expected[r.next];
        if (!expected) {
          ++r.outcome.unchecked;
        } else if (same_decision(*expected, a)) {
          ++r.outcome.same;
        } else {
          ++r.outcome.different;
          if (!r.outcome.first_difference) r.outcome.first_difference = AnswerDifference{frame.tick, *expected, a};
        }
        ++r.next;
      }
      if (r.awaiting) {
        if (now - r.first_sent_at > answer_timeout_) {
          r.outcome.failure = "no answer to the frame of tick " + std::to_string(frame.tick) + " within " +
                              std::to_string(std::chrono::duration_cast<std::chrono::seconds>(answer_timeout_).count()) +
                              " s";
        } else if (now - r.sent_at > std::chrono::milliseconds(200)) {
          r.frames.write(frame);  // written before the agent's reader matched, perhaps; it answers a repeat again
          r.sent_at = now;
          ++r.outcome.resent;
        }
        continue;
      }
      if (r.done()) continue;
    }
    if (pace_ == Pace::recorded && now - *started_ < std::chrono::nanoseconds(r.script.due_ns[r.next])) continue;
    const auto& frame = r.script.frames[r.next];
    r.frames.write(frame);
    if (frame.phase == wire::Phase::departed) {
      // As an arena does, no answer is awaited: the agent ends on it, perhaps before its answer
      // is delivered (docs/protocol.md §6).
      ++r.outcome.not_awaited;
      ++r.next;
      continue;
    }
    r.awaiting = true;
    r.sent_at = r.first_sent_at = now;
  }
  return any;
}

std::vector<RobotOutcome> Driver::outcomes() const {
  std::vector<RobotOutcome> out;
  for (const auto& r : robots_) out.push_back(r.outcome);
  return out;
}

std::string format_outcomes(const std::vector<RobotOutcome>& outcomes, bool redecided) {
  std::ostringstream out;
  const auto tick_text = [](std::int64_t t) { return t < 0 ? std::string("never") : "tick " + std::to_string(t); };
  std::uint64_t same = 0, different = 0, robots_different = 0, incomplete = 0;
  for (const auto& o : outcomes) {
    same += o.same;
    different += o.different;
    if (o.different > 0) ++robots_different;
    if (!o.failure.empty()) ++incomplete;
    out << "robot " << o.robot << ": " << o.answered << "/" << o.frames - o.not_awaited << " frames answered, " << o.same
        << " as recorded, " << o.different << " differ";
    if (o.unchecked > 0) out << ", " << o.unchecked << " without a recorded answer";
    if (o.not_awaited > 0) out << ", " << o.not_awaited << " departed (no answer awaited)";
    out << "; retreat: recorded " << tick_text(o.recorded_retreat_tick) << ", "
        << (redecided ? "re-decided " : "replayed ") << tick_text(o.replayed_retreat_tick);
    if (o.first_difference) {
      const auto& d = *o.first_difference;
      out << "; first difference at the frame of tick " << d.frame_tick << ": recorded " << answer_text(d.recorded)
          << ", replayed " << answer_text(d.replayed);
    }
    if (!o.failure.empty()) out << "; INCOMPLETE: " << o.failure;
    out << '\n';
  }
  out << outcomes.size() << " robots: " << same << " answers as recorded, " << different << " differ ("
      << robots_different << " robots)";
  if (incomplete > 0) out << ", " << incomplete << " robots incomplete";
  out << '\n';
  return out.str();
}

}  // namespace retreat::replay
