#pragma once
/// @file
/// Topic names of the contract (docs/protocol.md). Per-robot topics carry what a robot receives
/// or sends; shared keyed topics are for observation only.

#include <algorithm>
#include <optional>
#include <string>

#include "retreat/wire/messages.hpp"

namespace retreat::wire {

/// Default topic prefix.
inline constexpr const char* default_prefix = "retreat";

/// The participant user data of the arena, or of whoever plays its part for a robot (a robot's
/// link): docs/protocol.md §9. Informational; an agent takes it as "the arena has appeared".
inline constexpr const char* arena_user_data = "retreat:arena";
/// The participant user data of a recorder (retreat-record). With `run.recorders: n`, the arena
/// and every agent wait for n of them to match their writers before their robot's traffic
/// begins, so that a recording holds every sample (docs/protocol.md §9).
inline constexpr const char* recorder_user_data = "retreat:recorder";
/// What retreat-replay announces: it plays an arena's part to the agents it replays to.
inline constexpr const char* replay_user_data = "retreat:replay";

std::string proximity_topic(const std::string& prefix, RobotId robot);  ///< <p>/robot_<id>/proximity
std::string decision_topic(const std::string& prefix, RobotId robot);   ///< <p>/robot_<id>/decision
/// <p>/robot_<id>/plan: with run.plans, an agent's answer to a frame as a plan, agent -> arena.
/// A Decision sample whose fields mean: `time` the answered frame's time (which frame it
/// answers), `tick` the last tick the plan covers (>= the answered frame's tick), `retreat` the
/// decision at `tick`; at the ticks before it the decision stays what it was at the answered
/// frame (no retreat, unless the agent had decided before). Valid while the robot's input stays
/// unchanged: no new onset and the answered frame's phase (docs/protocol.md §6).
std::string plan_topic(const std::string& prefix, RobotId robot);
/// <p>/robot_<id>/tracked_pose: a real robot's pose in a mixed swarm (a Poses sample with
/// arena_id = id and one RobotPose of robot id), real robot -> arena.
std::string tracked_pose_topic(const std::string& prefix, RobotId robot);
std::string agent_status_topic(const std::string& prefix);              ///< <p>/agent_status
std::string arena_telemetry_topic(const std::string& prefix);           ///< <p>/arena_telemetry
std::string poses_topic(const std::string& prefix);                     ///< <p>/poses

/// Largest domain id the RTPS well-known port mapping allows with the default port parameters.
inline constexpr int max_domain_id = 232;
/// Most DDS domains one swarm may span (`dds.domains`).
inline constexpr int max_domains = 64;
/// Most domains a swarm whose first domain is @p first_domain (0..max_domain_id) may span:
/// max_domains, fewer where the domain ids end at max_domain_id. The one bound that the
/// scenario check and the transport's own check both apply.
constexpr int max_domains_from(int first_domain) {
  return std::max(1, std::min(max_domains, max_domain_id - first_domain + 1));
}
/// A swarm on @p domains domains from @p first_domain on carries robot @p robot's per-robot
/// topics on domain first_domain + robot mod domains; its shared topics are written on
/// first_domain and read on every one (docs/protocol.md §1).
int robot_domain(int first_domain, int domains, RobotId robot);
/// The robot id a per-robot topic name belongs to, or nullopt for shared topics.
std::optional<RobotId> robot_of_topic(const std::string& topic);

/// A topic prefix is 1..64 characters of [A-Za-z0-9_], '/' allowed between segments.
bool is_valid_prefix(const std::string& prefix);

}  // namespace retreat::wire
