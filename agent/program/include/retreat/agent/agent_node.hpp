#pragma once
/// @file
/// The one place where the agent's algorithm meets the wire: translates this robot's proximity
/// frames into observations, steps Algorithm 1, and publishes this robot's decision and status.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "retreat/agent/frame_journal.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/scenario/params.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::agent {

/// Counters of one agent process, for its status and exit report.
struct NodeCounters {
  std::uint64_t frames_received = 0;  ///< valid on the wire, handed to the algorithm
  std::uint64_t frames_dropped = 0;   ///< invalid on the wire, or rejected by the algorithm
  std::uint64_t decisions_sent = 0;  ///< answers written: decisions, or plans with run.plans
  /// With run.plans: frames the arena did not send, covered by our plan and acted on here with
  /// no new onset and the last frame's phase, at the frame clock's times (scenario::frame_clock).
  std::uint64_t frames_covered = 0;
  std::uint64_t statuses_sent = 0;
  std::uint64_t write_failures = 0;
  /// Arena incarnations seen: participants that matched this robot's decision topic as readers
  /// (1 in a run without restarts; one more for each arena resumed by `--resume`).
  std::uint32_t arena_incarnations = 0;
  /// Frames read back from the journal at start-up (a restarted agent), acted on again in order.
  std::uint64_t frames_recovered = 0;
};

class AgentNode {
 public:
  /// Creates the endpoints: a reader on `<prefix>/robot_<id>/proximity` only, writers on
  /// `<prefix>/robot_<id>/decision` (QosIntent::answers(): a dead arena cannot block it),
  /// with run.plans `<prefix>/robot_<id>/plan` (the same QoS; every frame is then answered with
  /// a plan, RetreatAgent::plan, instead of a decision), and `<prefix>/agent_status`. With @p journal_path, every accepted frame is journalled there
  /// before it is answered, and the frames an earlier process journalled are acted on first, so
  /// that the agent resumes exactly where that process stopped (FrameJournal; its errors pass on).
  AgentNode(const scenario::Scenario& scenario, std::uint32_t robot_id, transport::Transport& transport,
            const std::string& journal_path = {});

  /// Waits up to `timeout` for frames and handles every one received (on this thread).
  void spin_once(std::chrono::nanoseconds timeout);

  /// The robot has left the domain (a `departed` frame was accepted).
  bool departed() const { return departed_; }

  /// Whoever plays the arena's part has appeared: a frame arrived, one of this robot's topics is
  /// matched, or a participant announcing `retreat:arena` was discovered (an endless queue's
  /// spare agent waits for a robot the arena has not made yet). Checked at most once a second.
  bool arena_seen();

  /// Waits until every reader (the arena, recorders) acknowledged every decision, plan and
  /// status sent, up to `timeout` in all.
  void flush(std::chrono::nanoseconds timeout);

  const NodeCounters& counters() const { return counters_; }
  const RetreatAgent& agent() const { return agent_; }

 private:
  void handle(const wire::ProximityFrame& frame);
  /// With run.plans: acts on the frames between the last accepted one and @p tick, which the
  /// arena covered with our plan (no new onset, the last frame's phase, the frame clock's times).
  void act_on_covered(std::int64_t tick);
  /// Acts on one accepted frame's aftermath: journal, status (shared by sent and covered frames).
  void after_frame(const wire::ProximityFrame& frame, const FrameResult& result);
  /// This frame's answer: the decision, or with run.plans the plan.
  wire::Decision answer(const wire::ProximityFrame& frame, const FrameResult& result);
  /// Where answers go: the plan topic with run.plans, else the decision topic.
  transport::Writer<wire::Decision>& answer_writer() { return plans_ ? *plans_ : decisions_; }
  /// Acts on a journalled frame again, publishing nothing.
  void recover(const wire::ProximityFrame& frame);
  void publish_status(std::int64_t tick, double time);
  /// The status period a frame at @p time falls in: a status is published when it changes.
  std::int64_t status_slot(double time) const;
  /// The last frame tick in @p from .. @p to (on the frame clock) in the last status's period;
  /// from − 1 if @p from starts another.
  std::int64_t last_of_status_slot(std::int64_t from, std::int64_t to) const;
  /// Notices a new arena incarnation: a participant not seen before reading our decisions.
  void watch_decision_readers();
  /// Whether run.recorders recorders are in discovery and each is matched with every writer of
  /// this agent (decisions, plans, status): until then, what the agent writes could be missing
  /// from a recording, and the agent does not open its frames reader (so the arena, which waits
  /// for that reader, does not start).
  bool recorders_matched() const;
  /// Opens the frames reader unless run.recorders are still to match (until run.startup_timeout).
  bool open_frames();

  transport::Transport& transport_;
  std::uint32_t robot_id_;
  double status_period_;
  RetreatAgent agent_;
  transport::TopicSpec frames_topic_;
  std::uint32_t recorders_;
  std::chrono::steady_clock::time_point recorders_deadline_;
  std::optional<transport::Reader<wire::ProximityFrame>> frames_;  ///< opened by open_frames()
  transport::Writer<wire::Decision> decisions_;
  std::optional<transport::Writer<wire::Decision>> plans_;  ///< with run.plans
  FrameClock clock_;
  std::int64_t plan_horizon_;
  transport::Writer<wire::AgentStatus> statuses_;
  NodeCounters counters_;
  std::optional<wire::Decision> last_decision_;  ///< the last answer written (a plan with run.plans)
  std::int64_t last_answered_tick_ = -1;          ///< the frame tick it answers
  std::optional<wire::ProximityFrame> last_frame_;  ///< the last accepted frame (sent or covered)
  bool clock_warned_ = false;  ///< the frame-clock warning was printed (once per process)
  std::int64_t last_status_slot_ = -1;
  bool last_retreating_ = false;
  bool departed_ = false;
  std::set<std::string> decision_readers_;  ///< participant GUIDs that ever read our decisions
  std::chrono::steady_clock::time_point next_reader_check_{};
  std::uint64_t spins_ = 0;
  std::unique_ptr<FrameJournal> journal_;
  bool arena_seen_ = false;
  std::chrono::steady_clock::time_point next_arena_check_{};
};

/// The participant user data an agent announces: "retreat:agent:robot=<id>".
std::string agent_user_data(std::uint32_t robot_id);

}  // namespace retreat::agent
