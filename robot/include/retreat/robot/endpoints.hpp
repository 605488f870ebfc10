#pragma once
/// @file
/// The robot's side of the wire, shared by every producer of proximity frames: the simulated
/// arena (one per robot it serves) and a real robot's driver (retreat::robot::RobotLink). Both
/// create their endpoints and judge their agent's decisions here, so a driver speaks exactly
/// what the arena speaks (docs/protocol.md §2, §5, §6).

#include <chrono>
#include <cstdint>
#include <string>

#include "retreat/transport/transport.hpp"

namespace retreat::robot {

/// Lockstep: how long a robot's side waits for an answer before it sends the frame again
/// (a frame written while the two sides were still discovering each other may never arrive).
inline constexpr std::chrono::milliseconds resend_interval{200};

/// Robot @p id's decision reader, with the control QoS (every robot side has one).
transport::Reader<wire::Decision> decision_reader(transport::Transport& transport, const std::string& prefix,
                                                  wire::RobotId id);

/// Robot @p id's two per-robot endpoints, with the control QoS: the writer of its proximity
/// frames and the reader of its agent's decisions.
struct Endpoints {
  Endpoints(transport::Transport& transport, const std::string& prefix, wire::RobotId id);
  transport::Writer<wire::ProximityFrame> frames;
  transport::Reader<wire::Decision> decisions;
  /// Both endpoints are matched with an agent.
  bool matched() const { return frames.matched_count() > 0 && decisions.matched_count() > 0; }
};

/// With run.plans: robot @p id's plan reader (`<prefix>/robot_<id>/plan`, Decision samples
/// meaning a plan, see wire::plan_topic), with the control QoS: the arena's side.
transport::Reader<wire::Decision> plan_reader(transport::Transport& transport, const std::string& prefix,
                                              wire::RobotId id);

/// A real robot's tracked pose in a mixed swarm (`<prefix>/robot_<id>/tracked_pose`, a Poses
/// sample with arena_id = id and one RobotPose of robot id), with the control QoS: the robot's
/// writer and the arena's reader.
transport::Writer<wire::Poses> tracked_pose_writer(transport::Transport& transport, const std::string& prefix,
                                                   wire::RobotId id);
transport::Reader<wire::Poses> tracked_pose_reader(transport::Transport& transport, const std::string& prefix,
                                                   wire::RobotId id);

/// What a robot's side does with one decision (docs/protocol.md §6).
enum class DecisionVerdict {
  accepted,  ///< acted on (retreat is ORed into the robot's sticky retreat)
  future,    ///< answers a tick not yet published: ignored, counted
  stale,     ///< lockstep: answers an earlier tick, which is settled: ignored, counted
};

/// The verdict on decision @p d when the newest published tick is @p current. In real time a
/// late decision (tick < current) is accepted; in lockstep only the current tick's answer is.
DecisionVerdict judge(const wire::Decision& d, std::int64_t current, bool lockstep);

/// The verdict on plan @p plan when the frame awaiting an answer is tick @p tick at @p time: it
/// answers that frame if it carries the frame's time and covers at least its tick; one with a
/// later time answers a frame not yet published (future), any other an earlier one (stale).
DecisionVerdict judge_plan(const wire::Decision& plan, std::int64_t tick, double time);

}  // namespace retreat::robot
