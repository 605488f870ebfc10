#pragma once
/// @file
/// A real robot's link to its agent: one call to join the swarm as robot i, one to report the
/// robot's proximity signal with its own clock, one to receive its agent's decisions. It plays
/// the arena's part for one robot (docs/protocol.md §1) with the arena's own endpoints and
/// decision rules (retreat/robot/endpoints.hpp), so types, QoS, topics, discovery settings,
/// user data, lockstep re-sends and bad samples are handled as the arena handles them.
/// docs/robot-guide.md walks through it; retreat/robot/robot.h is the same for C.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "retreat/robot/endpoints.hpp"
#include "retreat/scenario/params.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::robot {

/// How long leaving waits for the agent to acknowledge the last frames.
inline constexpr std::chrono::seconds leave_timeout{2};

/// How a robot joins.
struct LinkOptions {
  wire::RobotId robot_id = 0;
  std::string vendor = "cyclonedds";  ///< "fastdds" or "cyclonedds" (transport::dds_vendors())
  std::string prefix = wire::default_prefix;  ///< the swarm's topic prefix (dds.prefix)
  /// Domain, vendor XML profile (empty: the built-in loopback-only settings, docs/dds-profiles.md),
  /// DDS Security files. Name and user data are filled in when empty
  /// (`retreat-robot/robot_<i>`, `retreat:arena`).
  transport::ParticipantOptions participant{};
  /// Lockstep (run.mode lockstep): only the answer to the newest frame counts, and await_answer()
  /// re-sends the frame until it comes. Real time: late answers count too.
  bool lockstep = false;
  /// A real robot in a mixed swarm (`arena.external_robots`): the arena writes its frames from
  /// its tracked pose, so the link writes no frames; it publishes the robot's pose
  /// (report_pose()) and reads its decisions. Real time only.
  bool tracked = false;
};

/// A robot's options from the swarm's scenario: dds.vendor, dds.domain, dds.prefix, dds.profile,
/// DDS Security (the PKI's `driver_<i>` identity, deploy/security/make-swarm-pki.sh: robot i's
/// frames and tracked pose, its decisions, nothing else), run.mode and whether robot i is tracked.
/// @throws std::invalid_argument when the scenario's vendor is `inmemory` (a robot needs DDS).
LinkOptions link_options(const scenario::Scenario& scenario, wire::RobotId robot_id);

/// Checks @p options: vendor built, prefix valid, participant options valid.
/// @throws std::invalid_argument naming the value and what is allowed.
void validate(const LinkOptions& options);

/// What the link has done.
struct LinkCounters {
  std::uint64_t frames_sent = 0;       ///< reports published as frames (tracked: poses)
  std::uint64_t frames_resent = 0;     ///< lockstep re-sends while awaiting an answer
  std::uint64_t reports_refused = 0;   ///< bad reports (time, phase, after departed): not sent
  std::uint64_t write_failures = 0;    ///< frames the middleware did not accept
  std::uint64_t decisions_accepted = 0;
  std::uint64_t decisions_future = 0;  ///< answered a tick not yet published
  std::uint64_t decisions_stale = 0;   ///< lockstep: answered an earlier tick
  std::uint64_t decisions_invalid = 0; ///< dropped by validation (docs/protocol.md §7)
};

/// One robot's link. Not thread-safe: call it from the robot's control loop.
class RobotLink {
 public:
  /// Joins the swarm: a DDS participant on the options' domain with robot i's endpoints.
  /// @throws std::invalid_argument for bad options; std::runtime_error if the middleware fails.
  explicit RobotLink(LinkOptions options);
  /// Leaves the swarm, first waiting up to leave_timeout until the agent has acknowledged every
  /// frame (so that a last `departed` frame arrives).
  ~RobotLink();
  RobotLink(const RobotLink&) = delete;
  RobotLink& operator=(const RobotLink&) = delete;

  /// Waits until robot i's agent has matched both topics, up to @p timeout. Frames published
  /// before that are lost to the agent (the topics are volatile): report after this returns true.
  bool wait_for_agent(std::chrono::nanoseconds timeout);
  /// Driver: the agent matched both topics. Tracked: the agent's decisions and the arena's pose
  /// reader are matched.
  bool agent_matched() const;

  /// Publishes the robot's proximity signal as the next frame (ticks 0, 1, 2, ...).
  /// @p time: the robot's own clock [s], finite, >= 0, never going back; best counted from the
  /// robot's start (now() is such a clock). @p new_onsets: encounters that began since the
  /// previous report. Any rate works: the agent's steps follow its own dt, not the frames
  /// (docs/protocol.md §6). Returns the frame's tick; std::nullopt for a refused report (time not
  /// finite, negative or earlier than the previous report's, a report after `departed`): it is
  /// counted, refused_reason() says why, and its onsets go with the next accepted report.
  std::optional<std::int64_t> report(double time, wire::Phase phase, bool in_contact,
                                     std::uint32_t new_onsets);

  /// Tracked robots: publishes the robot's pose at its own time [s] (finite, >= 0, never going
  /// back), @p x, @p y [m] in the arena's frame (origin at the centre of D), heading @p theta
  /// [rad]. Returns the pose's sequence number; std::nullopt for a refused report (counted, as
  /// report()), and for a link that is not tracked.
  std::optional<std::int64_t> report_pose(double time, double x, double y, double theta);

  /// Takes every decision that has arrived, without waiting. Returns true when the newest frame
  /// has been answered.
  bool poll();
  /// Waits up to @p timeout for the answer to the newest frame, re-sending the frame every
  /// resend_interval meanwhile (the arena does the same in lockstep). Returns true when it came.
  bool await_answer(std::chrono::nanoseconds timeout);

  /// The agent has decided that the robot leaves the region (sticky: never false again).
  bool retreat() const { return retreat_; }
  /// The newest accepted decision.
  const std::optional<wire::Decision>& last_decision() const { return last_decision_; }
  /// The newest published frame's tick.
  std::optional<std::int64_t> tick() const { return last_frame_ ? std::optional(last_frame_->tick) : std::nullopt; }
  /// Seconds since the link was created (steady clock): a robot clock that starts at 0.
  double now() const;
  LinkCounters counters() const;
  /// The remote writers the link's decision reader is matched with (isolation: only the robot's
  /// own agent should be among them).
  std::vector<transport::RemoteEndpoint> decision_sources() const;
  /// Why the last refused report was refused ("" if none was).
  const std::string& refused_reason() const { return refused_reason_; }
  const LinkOptions& options() const { return options_; }

 private:
  /// Counts a refused report or pose and keeps @p reason for refused_reason().
  std::nullopt_t refuse(std::string reason);
  /// Why @p time cannot follow @p previous, the time of the previous @p what ("report", "pose"):
  /// not finite, negative, or going back; "" when it can.
  static std::string clock_refusal(double time, const std::optional<double>& previous, const char* what);

  LinkOptions options_;
  std::unique_ptr<transport::Transport> transport_;
  std::optional<Endpoints> endpoints_;                        ///< driver: the arena's endpoints
  std::optional<transport::Reader<wire::Decision>> tracked_decisions_;  ///< tracked
  std::optional<transport::Writer<wire::Poses>> poses_;                 ///< tracked
  std::optional<wire::Poses> last_pose_;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::optional<wire::ProximityFrame> last_frame_;
  std::optional<wire::Decision> last_decision_;
  std::uint32_t pending_onsets_ = 0;  ///< onsets of refused reports, sent with the next frame
  bool answered_ = false;
  bool retreat_ = false;
  LinkCounters counters_;
  std::string refused_reason_;
  std::vector<wire::Decision> taken_;
};

}  // namespace retreat::robot
