#pragma once
/// @file
/// The one place where the simulated world meets the wire: publishes each robot's proximity
/// frames on its own topic, reads each robot's decision from its own topic, publishes
/// ground-truth telemetry and poses, and steps the world in lockstep or real time.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "retreat/physics/sensor_noise.hpp"
#include "retreat/physics/world.hpp"
#include "retreat/robot/endpoints.hpp"
#include "retreat/scenario/params.hpp"
#include "retreat/transport/transport.hpp"
#include "retreat/arena/run_recorder.hpp"

namespace retreat::arena {

/// The ground-truth telemetry message of the world's state @p t (arena id 0): the one
/// translation of physics::Telemetry to the wire, for the arena and the launcher's progress line.
wire::ArenaTelemetry telemetry_message(const physics::Telemetry& t, std::uint32_t lost_agents,
                                       double ticks_per_second);

/// Counters of decisions the arena did not act on.
struct DecisionCounters {
  std::uint64_t applied = 0;        ///< retreat decisions passed to the world
  std::uint64_t stale = 0;          ///< lockstep: answered a past tick (or came from a lost agent)
  std::uint64_t future = 0;         ///< answered a tick not yet published
  std::uint64_t unknown_robot = 0;  ///< robot the world does not have
  std::uint64_t invalid = 0;        ///< dropped by the transport's validation
  std::uint64_t resent_frames = 0;  ///< lockstep frames sent again because no answer came
  /// Lockstep: robot-ticks whose agent was silent past run.agent_timeout but still there (its
  /// answer writer matched), so the arena waited instead of declaring it lost.
  std::uint64_t slow_answers = 0;
  std::uint64_t received = 0;       ///< valid decisions (or plans) taken from the wire
  std::uint64_t planned = 0;        ///< run.plans: robot-ticks decided by a plan, no frame sent
};

class ArenaNode {
 public:
  using KeepGoing = std::function<bool()>;

  /// `recorder` may be null (no run directory).
  ArenaNode(const scenario::Scenario& scenario, transport::Transport& transport,
            RunRecorder* recorder);
  ~ArenaNode();

  /// Waits until the agent of every robot that exists now has matched both its proximity and
  /// its decision topic, or until `timeout`; agents that did not are counted lost. Returns the
  /// number of agents matched.
  std::uint32_t wait_for_agents(std::chrono::nanoseconds timeout, const KeepGoing& keep_going);

  /// Publishes the current tick's frames (and telemetry and poses when due).
  void publish_tick();

  /// With run.plans: whether the run's last tick is sent to every robot, its plan in force or
  /// not (the default), so that every agent acts on the ticks its plan covered and publishes
  /// their statuses before the run ends. Off where nobody reads the statuses (run_in_memory,
  /// whose bus is the run's own), saving up to run.plan_horizon steps per agent; the trajectory
  /// is the same either way.
  void settle_plans_at_end(bool on) { settle_plans_at_end_ = on; }
  /// Waits, up to @p timeout in all, until every reader acknowledged every frame, telemetry and
  /// poses sample written (with run.recorders: the recorders' last samples). Returns true if all
  /// were acknowledged in time.
  bool flush(std::chrono::nanoseconds timeout);

  /// Lockstep: receives decisions until every live agent answered the current tick; an agent
  /// silent for run.agent_timeout is declared lost. Returns false if `keep_going` said stop.
  bool collect_lockstep(const KeepGoing& keep_going);

  /// Takes every decision that has arrived, without waiting (real time, in-process). Returns
  /// all_answered() (found in the same pass over the robots).
  bool collect_available();

  /// The robots sent a frame by the last publish_tick(), in id order: with run.plans, those
  /// whose input changed or whose plan ended (and only their agents have anything to do).
  const std::vector<std::uint32_t>& frames_sent() const { return sent_; }

  /// True when every live agent has answered the current tick.
  bool all_answered() const;

  /// Applies the current tick's decisions, hashes the tick, steps the world, records telemetry.
  void step();

  /// A resumed arena (retreat-arena --resume): steps the world from tick 0 to
  /// `ticks` exactly as the dead arena did, applying the journalled retreat decisions at their
  /// ticks, publishing nothing and writing no telemetry row (the rows are on disk). The world,
  /// its RNG, the agents' records and the trajectory hash are then where the dead arena left them.
  void replay(std::int64_t ticks, const RetreatJournal& journal);

  /// The run is over: duration reached, or every robot has departed and none waits.
  bool finished() const;

  /// Writes the run directory's summary; returns the summary.
  RunSummary finish(double wall_seconds);

  const physics::World& world() const { return *world_; }
  /// The counters so far (`invalid` summed over every robot's reader now).
  DecisionCounters decisions() const;
  std::uint32_t agents_lost() const;
  /// A mixed swarm's real robots: poses taken, dropped, frozen and lost so far.
  ExternalCounters external_counters() const;
  std::int64_t tick() const;

 private:
  struct Robot;
  /// What every tick reads or writes of one robot, kept apart from its Robot (one array, by id).
  struct TickState {
    std::int64_t plan_through = -1;   ///< run.plans: the last tick its plan covers (-1: none)
    std::uint32_t sensed_onsets = 0;  ///< the current frame's onsets as the robot's sensor reports them
    wire::Phase phase = wire::Phase::waiting;
    wire::Phase plan_phase = wire::Phase::waiting;  ///< the phase of the frame its plan answered
    bool expecting = false;  ///< a frame of the current tick is waiting for this agent's answer
    bool answered = false;
    bool retreat = false;       ///< the answer for the current tick (or, real time, any answer)
    bool commanded = false;     ///< the world was told to retreat this robot
    bool plan_retreat = false;  ///< the plan's decision at plan_through
    bool lost = false;          ///< its AgentRecord's `lost` (set by declare_lost only)
  };
  static bool owes_answer(const TickState& t) { return t.expecting && !t.answered && !t.lost; }
  /// The robot with this id; every id up to it gets its Robot and TickState.
  Robot& robot(std::uint32_t id);
  /// Robot @p id's TickState (made with its Robot, as robot() does), without reaching its Robot.
  TickState& tick_state(std::uint32_t id);
  void take_decisions(Robot& r, std::int64_t current);
  /// run.plans: true when plan @p p of robot @p r needs no action: the robot has departed (the
  /// answer to its last frame), or the plan is counted dropped (unknown robot, future, stale or
  /// from a lost agent); false when it answers the frame awaiting an answer.
  bool settled_plan(const Robot& r, const wire::Decision& p, std::int64_t current);
  /// The current tick is at or past run.duration: the run's last.
  bool duration_reached() const;
  /// Declares robot @p r's agent lost at simulated time @p at (counted in agents_lost() if it
  /// had matched).
  void declare_lost(Robot& r, double at);
  /// run.plans: takes robot @p r's plans; one that answers the frame awaiting an answer is kept.
  void take_plans(Robot& r, std::int64_t current);
  /// run.plans, at the end: counts the plans still unread (collect_available() reads only the
  /// robots sent a frame) as take_plans() would, acting on none: a departed robot's last answer
  /// is not counted, every other one is dropped.
  void count_leftover_plans();
  /// Acts on robot @p id's decision for the current tick (from the wire or from its plan).
  void act_on_answer(std::uint32_t id, bool retreat);
  /// run.plans: a robot's decision at @p tick, a tick its plan (in @p t) covers.
  static bool plan_decision(const TickState& t, std::int64_t tick);
  /// Real robots: applies every valid tracked pose that arrived (dropping and counting those
  /// going back in time or jumping), then freezes or loses those whose pose is too old.
  void take_external_poses();
  void resend_unanswered();
  /// Whether robot @p r's agent is still there: a writer of its answers is matched.
  static bool agent_present(const Robot& r);
  void publish_observations();
  /// step() and replay(): `journal` null means live (decisions from the wire, journalled).
  void advance(const RetreatJournal* journal);

  scenario::Scenario scenario_;
  transport::Transport& transport_;
  RunRecorder* recorder_;
  std::unique_ptr<physics::World> world_;
  physics::SensorNoise sensor_;  ///< each robot's sensor (arena.missed_onsets, arena.false_onsets)
  std::vector<std::unique_ptr<Robot>> robots_;  ///< by robot id (ids are 0 .. robot_count()−1)
  std::vector<TickState> ticks_;                ///< by robot id, as robots_
  std::vector<std::uint32_t> sent_;             ///< frames_sent()
  std::vector<wire::Decision> taken_;           ///< take_decisions' buffer, kept between calls
  std::vector<wire::Poses> taken_poses_;        ///< take_external_poses' buffer
  ExternalCounters external_;
  transport::Writer<wire::ArenaTelemetry> telemetry_;
  transport::Writer<wire::Poses> poses_;
  TrajectoryHash hash_;
  DecisionCounters counters_;
  std::int64_t last_published_slot_ = -1;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  std::uint32_t agents_started_ = 0;
  bool settle_plans_at_end_ = true;
  std::uint32_t agents_lost_ = 0;  ///< agents that matched and were declared lost (declare_lost)
  std::int64_t resumed_at_tick_ = -1;
};

}  // namespace retreat::arena
