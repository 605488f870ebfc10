#include "retreat/robot/robot_link.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <thread>

#include "retreat/core/enum_names.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::robot {
namespace {

/// @p options after filling in the defaults and checking them (so that members are built from
/// valid options only).
LinkOptions completed(LinkOptions options) {
  const auto robot = "robot_" + std::to_string(options.robot_id);
  if (options.participant.name.empty()) options.participant.name = "retreat-robot/" + robot;
  if (options.participant.user_data.empty()) options.participant.user_data = wire::arena_user_data;
  validate(options);
  return options;
}

}  // namespace

LinkOptions link_options(const scenario::Scenario& s, wire::RobotId robot_id) {
  if (s.dds.vendor == scenario::Vendor::inmemory) {
    throw std::invalid_argument("dds.vendor 'inmemory' cannot link a robot: use fastdds or cyclonedds");
  }
  if (s.run.plans) {
    // The agent would answer on the plan topic, which a link does not read: refuse, not hang.
    throw std::invalid_argument(
        "run.plans = true: a robot link sends a frame every tick and reads decisions, not plans; "
        "set run.plans: false in the scenario its agent reads too");
  }
  LinkOptions options;
  options.robot_id = robot_id;
  options.vendor = std::string(name_of(s.dds.vendor));
  options.prefix = s.dds.prefix;
  options.participant =
      scenario::robot_participant_options(s, robot_id, "retreat-robot/robot_" + std::to_string(robot_id),
                                          wire::arena_user_data, "driver_" + std::to_string(robot_id));
  options.lockstep = s.run.mode == scenario::RunMode::lockstep;
  options.tracked = robot_id < s.arena.external_robots;  // a real robot of a mixed swarm
  return options;
}

void validate(const LinkOptions& options) {
  const auto vendors = transport::dds_vendors();
  if (std::find(vendors.begin(), vendors.end(), options.vendor) == vendors.end()) {
    std::string allowed;
    for (const auto& v : vendors) allowed += (allowed.empty() ? "" : ", ") + v;
    throw std::invalid_argument("vendor '" + options.vendor + "' is not a DDS vendor of this build: use one of " +
                                allowed);
  }
  if (!wire::is_valid_prefix(options.prefix)) {
    throw std::invalid_argument("prefix '" + options.prefix +
                                "' is not valid: 1 to 64 characters of [A-Za-z0-9_], '/' between segments");
  }
  transport::validate(options.participant);
  if (options.tracked && options.lockstep) {
    throw std::invalid_argument("a tracked robot (a real robot of a mixed swarm) runs in real time: lockstep must be off");
  }
}

RobotLink::RobotLink(LinkOptions options)
    : options_(completed(std::move(options))),
      transport_(transport::make_transport(options_.vendor, options_.participant)) {
  if (options_.tracked) {
    tracked_decisions_.emplace(decision_reader(*transport_, options_.prefix, options_.robot_id));
    poses_.emplace(tracked_pose_writer(*transport_, options_.prefix, options_.robot_id));
  } else {
    endpoints_.emplace(*transport_, options_.prefix, options_.robot_id);
  }
}

RobotLink::~RobotLink() {
  // The last frame (typically `departed`, which ends the agent) must reach the agent before the
  // participant goes: a participant deleted right after a write may take it along unsent.
  if (endpoints_) endpoints_->frames.wait_for_acknowledgments(leave_timeout);
  if (poses_) poses_->wait_for_acknowledgments(leave_timeout);
}

bool RobotLink::agent_matched() const {
  if (endpoints_) return endpoints_->matched();
  return tracked_decisions_->matched_count() > 0 && poses_->matched_count() > 0;
}

bool RobotLink::wait_for_agent(std::chrono::nanoseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!agent_matched()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

std::nullopt_t RobotLink::refuse(std::string reason) {
  ++counters_.reports_refused;
  refused_reason_ = std::move(reason);
  return std::nullopt;
}

std::string RobotLink::clock_refusal(double time, const std::optional<double>& previous, const char* what) {
  if (!std::isfinite(time) || time < 0.0) return "time " + std::to_string(time) + " s refused: must be finite and >= 0";
  if (previous && time < *previous) {
    return "time " + std::to_string(time) + " s refused: earlier than the previous " + what + "'s " +
           std::to_string(*previous) + " s (the clock went back)";
  }
  return "";
}

std::optional<std::int64_t> RobotLink::report(double time, wire::Phase phase, bool in_contact,
                                              std::uint32_t new_onsets) {
  const auto onsets = static_cast<std::uint64_t>(pending_onsets_) + new_onsets;
  pending_onsets_ = static_cast<std::uint32_t>(std::min<std::uint64_t>(onsets, UINT32_MAX));
  const auto previous = last_frame_ ? std::optional(last_frame_->time) : std::nullopt;
  if (auto why = clock_refusal(time, previous, "report"); !why.empty()) return refuse(std::move(why));
  if (static_cast<std::uint8_t>(phase) >= wire::phase_count) {
    return refuse("phase " + std::to_string(static_cast<unsigned>(phase)) + " refused: must be 0..3");
  }
  if (options_.tracked) {
    return refuse("report refused: a tracked robot's frames come from the arena (use report_pose)");
  }
  if (last_frame_ && last_frame_->phase == wire::Phase::departed) {
    return refuse("report refused: the robot has departed (its agent has stopped)");
  }
  const std::int64_t tick = last_frame_ ? last_frame_->tick + 1 : 0;
  last_frame_ = wire::ProximityFrame{options_.robot_id, tick, time, phase, in_contact, pending_onsets_};
  pending_onsets_ = 0;
  answered_ = false;
  if (endpoints_->frames.write(*last_frame_) == transport::WriteResult::ok) {
    ++counters_.frames_sent;
  } else {
    ++counters_.write_failures;
  }
  return tick;
}

std::optional<std::int64_t> RobotLink::report_pose(double time, double x, double y, double theta) {
  if (!options_.tracked) {
    return refuse("pose refused: only a tracked robot (LinkOptions::tracked) reports its pose");
  }
  const auto previous = last_pose_ ? std::optional(last_pose_->time) : std::nullopt;
  if (auto why = clock_refusal(time, previous, "pose"); !why.empty()) return refuse(std::move(why));
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(theta)) {
    return refuse("pose refused: x, y and theta must be finite");
  }
  const std::int64_t tick = last_pose_ ? last_pose_->tick + 1 : 0;
  wire::Poses pose;
  pose.arena_id = options_.robot_id;
  pose.tick = tick;
  pose.time = time;
  pose.robots.push_back({options_.robot_id, static_cast<float>(x), static_cast<float>(y),
                         static_cast<float>(theta), retreat_ ? wire::Phase::retreating : wire::Phase::inside, false});
  if (poses_->write(pose) == transport::WriteResult::ok) {
    ++counters_.frames_sent;
  } else {
    ++counters_.write_failures;
  }
  last_pose_ = std::move(pose);
  return tick;
}

bool RobotLink::poll() {
  auto& decisions = endpoints_ ? endpoints_->decisions : *tracked_decisions_;
  decisions.take(taken_);
  for (const auto& d : taken_) {
    // A tracked robot publishes no frames: every tick's answer is in its past.
    const auto current = options_.tracked ? INT64_MAX : last_frame_ ? last_frame_->tick : -1;
    switch (judge(d, current, options_.lockstep)) {
      case DecisionVerdict::future:
        ++counters_.decisions_future;
        break;
      case DecisionVerdict::stale:
        ++counters_.decisions_stale;
        break;
      case DecisionVerdict::accepted:
        ++counters_.decisions_accepted;
        retreat_ = retreat_ || d.retreat;
        if (d.tick == current) answered_ = true;
        if (!last_decision_ || d.tick >= last_decision_->tick) last_decision_ = d;
        break;
    }
  }
  return answered_;
}

bool RobotLink::await_answer(std::chrono::nanoseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto next_resend = std::chrono::steady_clock::now() + resend_interval;
  while (!poll() && last_frame_ && endpoints_) {
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) return false;
    if (now >= next_resend) {
      endpoints_->frames.write(*last_frame_);  // the agent answers a repeated tick again
      ++counters_.frames_resent;
      next_resend = now + resend_interval;
    }
    transport_->wait(std::min(deadline, next_resend) - now);
  }
  return answered_;
}

double RobotLink::now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

std::vector<transport::RemoteEndpoint> RobotLink::decision_sources() const {
  return (endpoints_ ? endpoints_->decisions : *tracked_decisions_).matched();
}

LinkCounters RobotLink::counters() const {
  LinkCounters c = counters_;
  c.decisions_invalid = (endpoints_ ? endpoints_->decisions : *tracked_decisions_).stats().dropped_total();
  return c;
}

}  // namespace retreat::robot
