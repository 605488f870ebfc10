#pragma once
/// @file
/// retreat-replay's work: plays a recording's proximity frames to live agents, one robot or all,
/// and compares their answers with the recorded ones; or, with another controller, re-decides
/// the recorded inputs tick by tick and reports where the decisions differ (docs/recording.md).
/// The driver speaks the wire contract like an arena in lockstep (docs/protocol.md §6): it sends
/// a robot's next frame once the robot's agent has answered the previous one, each robot at its
/// own pace (agents do not depend on one another). It runs over any transport: DDS with agent
/// processes, or the in-memory transport with agents in the same process.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "retreat/replay/recording.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::replay {

enum class Pace {
  lockstep,  ///< a robot's next frame as soon as its agent answered the previous one
  recorded,  ///< besides, not before the recorder took it (relative to the first frame)
};

struct ReplayOptions {
  std::vector<std::uint32_t> robots;  ///< the robots to replay; empty: every robot with frames
  Pace pace = Pace::lockstep;
  /// Empty: the recorded rule. A registered controller: re-decide every tick with it.
  std::string controller;
  /// `agent.key=value` overrides of the agents' parameters: re-decide every tick with them.
  std::vector<std::string> agent_overrides;
  /// Re-deciding (another rule or other parameters: every tick, run.plans off, compared with the
  /// recorded decisions) rather than checking that the agents answer as recorded.
  bool redecide() const { return !controller.empty() || !agent_overrides.empty(); }
};

/// What the driver sends one robot, and what the recording says it answered.
struct RobotScript {
  std::uint32_t robot = 0;
  std::vector<wire::ProximityFrame> frames;        ///< in tick order, one per tick
  std::vector<std::uint64_t> due_ns;               ///< Pace::recorded: when, after the first frame
  std::vector<std::optional<wire::Decision>> expected;  ///< the recorded answer to each frame, if recorded
  std::int64_t recorded_retreat_tick = -1;         ///< the tick the recorded agent retreats at (-1: never)
};

/// One difference between a recorded and a replayed answer.
struct AnswerDifference {
  std::int64_t frame_tick = 0;
  wire::Decision recorded, replayed;
};

struct RobotOutcome {
  std::uint32_t robot = 0;
  std::uint64_t frames = 0;     ///< frames in its script
  std::uint64_t answered = 0;   ///< frames answered by its agent
  std::uint64_t same = 0;       ///< answers equal to the recorded ones
  std::uint64_t different = 0;  ///< answers not equal to them
  std::uint64_t unchecked = 0;  ///< answers to frames whose recorded answer is missing
  std::uint64_t resent = 0;     ///< frames sent again for want of an answer
  std::uint64_t not_awaited = 0;  ///< departed frames: sent, no answer awaited (as an arena does)
  std::optional<AnswerDifference> first_difference;
  std::int64_t recorded_retreat_tick = -1;
  std::int64_t replayed_retreat_tick = -1;
  std::string failure;  ///< why its replay stopped early (no answer in time); empty if complete
};

/// The scenario the replayed agents run: the recording's, with no recorders to wait for; when
/// re-deciding, the controller and the overrides applied, deciding every tick (run.plans off).
/// @throws scenario::ConfigError for an override that is not a valid `agent.*` value.
scenario::Scenario agent_scenario(const Recording& recording, const ReplayOptions& options);

/// Each replayed robot's frames and expected answers. Checking, the recorded frames (a re-sent
/// tick once). Re-deciding, every tick from the robot's first frame to its last: the ticks a
/// plan covered are filled as the agent itself fills them (its last frame's phase, no onset, the
/// frame clock's time; docs/protocol.md §6), and the expected answer at tick k is the recorded
/// decision then (sticky: retreat from the recorded retreat tick on).
/// @throws RecordingError naming a robot that has no frames in the recording.
std::vector<RobotScript> make_scripts(const Recording& recording, const ReplayOptions& options);

/// Plays scripts over one transport, as one participant.
class Driver {
 public:
  /// @p plans: the agents answer with plans (on `<prefix>/robot_<id>/plan`) instead of decisions.
  /// @p answer_timeout: a robot whose agent does not answer a frame within it (wall time, frames
  /// re-sent every 200 ms meanwhile) is given up, its outcome says so.
  Driver(transport::Transport& transport, const std::string& prefix, std::vector<RobotScript> scripts,
         bool plans, Pace pace, std::chrono::nanoseconds answer_timeout);

  /// Whether every robot's frame writer and answer reader are matched with its agent.
  bool matched() const;
  /// Sends what is due and takes the answers that arrived; @p now is the wall clock. Returns
  /// false once every robot is done (answered its last frame, or given up).
  bool step(std::chrono::steady_clock::time_point now);

  std::vector<RobotOutcome> outcomes() const;

 private:
  struct Robot;
  std::vector<Robot> robots_;
  bool plans_;
  Pace pace_;
  std::chrono::nanoseconds answer_timeout_;
  std::optional<std::chrono::steady_clock::time_point> started_;
  std::vector<wire::Decision> taken_;

 public:
  ~Driver();
  Driver(Driver&&) noexcept;
  Driver& operator=(Driver&&) = delete;
};

/// One line per robot and a total, for the terminal.
std::string format_outcomes(const std::vector<RobotOutcome>& outcomes, bool redecided);

}  // namespace retreat::replay
