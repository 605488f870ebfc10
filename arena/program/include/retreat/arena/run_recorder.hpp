#pragma once
/// @file
/// Writes a run directory: the resolved scenario, per-tick telemetry (CSV), per-agent history
/// (CSV), encounter records (CSV, when asked), and summary.json with the trajectory hash.

#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "retreat/physics/world.hpp"
#include "retreat/scenario/params.hpp"

namespace retreat::arena {

/// SHA-256 over every tick's (tick, robot id, phase, decision), so that two runs can be
/// compared for identity whatever carried the messages.
class TrajectoryHash {
 public:
  TrajectoryHash();
  ~TrajectoryHash();
  TrajectoryHash(const TrajectoryHash&) = delete;
  TrajectoryHash& operator=(const TrajectoryHash&) = delete;
  /// Adds one robot's record at @p tick: 8 bytes tick, 4 bytes robot, 1 byte phase, 1 byte
  /// decision, little endian. Inline: it runs once per robot and tick, and is a copy into a buffer
  /// (SHA-256 of the concatenation is the same however it is fed, so the buffer goes to SHA-256
  /// 64 KiB at a time).
  void add(std::int64_t tick, std::uint32_t robot, std::uint8_t phase, bool retreat) {
    if (used_ + record_size > pending_.size()) flush();
    unsigned char* record = pending_.data() + used_;
    const auto t = static_cast<std::uint64_t>(tick);
    for (int i = 0; i < 8; ++i) record[i] = static_cast<unsigned char>(t >> (8 * i));
    for (int i = 0; i < 4; ++i) record[8 + i] = static_cast<unsigned char>(robot >> (8 * i));
    record[12] = phase;
    record[13] = retreat ? 1 : 0;
    used_ += record_size;
  }
  /// The hash so far (every record added) as a link of the per-tick chain: the first 8 bytes of
  /// its SHA-256, little endian. Called after a tick's last record, link k is the trajectory hash
  /// of the run cut after tick k, so two runs' chains agree up to the tick where they diverge.
  std::uint64_t link();
  /// Hex digest; the hash cannot be extended afterwards.
  std::string finish();

 private:
  static constexpr std::size_t record_size = 14;
  /// Feeds the records not yet hashed to SHA-256.
  void flush();

  struct State;
  std::unique_ptr<State> state_;
  std::vector<unsigned char> pending_;  ///< records not yet hashed (64 KiB)
  std::size_t used_ = 0;
};

/// What the arena knows about one agent at the end of the run.
struct AgentRecord {
  std::uint32_t robot = 0;
  bool matched = false;    ///< its agent was matched at start (or when its robot appeared)
  bool lost = false;       ///< declared lost (stopped answering in lockstep)
  double lost_at = -1.0;   ///< simulated time it was declared lost [s]
  bool retreated = false;  ///< its agent decided to retreat
  double retreat_at = -1.0;
};

/// Everything summary.json reports.
/// A mixed swarm's real robots (arena.external_robots), as the arena saw their poses.
struct ExternalCounters {
  std::uint64_t poses_accepted = 0;
  std::uint64_t poses_invalid = 0;     ///< dropped by validation (another robot's, NaN, ...)
  std::uint64_t poses_clock_back = 0;  ///< dropped: earlier than the robot's previous pose
  std::uint64_t poses_jumped = 0;      ///< dropped: a move faster than arena.external_max_speed
  std::uint64_t frozen = 0;            ///< times a real robot's pose became older than external_frozen_after
  std::uint32_t lost = 0;              ///< real robots lost (no pose for external_lost_after)
};

struct RunSummary {
  std::int64_t ticks = 0;
  double wall_seconds = 0.0;
  std::uint32_t agents_started = 0;
  std::uint32_t agents_lost = 0;
  std::uint64_t decisions_dropped = 0;  ///< unknown robot, past or future tick, invalid
  std::uint64_t frames_resent = 0;      ///< lockstep frames re-sent for want of an answer
  std::uint64_t slow_answers = 0;       ///< lockstep: robot-ticks waited for past run.agent_timeout (agent still matched)
  std::uint64_t decisions_received = 0;  ///< decisions this arena process acted on or counted
  std::uint64_t decisions_planned = 0;   ///< run.plans: robot-ticks decided by a plan, no frame sent
  std::int64_t resumed_at_tick = -1;    ///< --resume: the tick this process took over at
  std::string trajectory_sha256;
  std::string dds;
  ExternalCounters external;  ///< written to summary.json when the run has real robots
};

/// Retreat decisions a run acted on, tick by tick (`retreats.csv`): with the scenario and its
/// seed, all a resumed arena needs to rebuild the world exactly (docs/protocol.md, "Time").
using RetreatJournal = std::multimap<std::int64_t, std::uint32_t>;  // tick -> robot

class RunRecorder {
 public:
  /// Creates `dir` (and parents) and writes scenario.yaml. Throws std::runtime_error when the
  /// directory cannot be written, and std::invalid_argument when it holds a recorded run already
  /// (recorded_run_in) and `resume` is false: a run directory is never overwritten. With
  /// `resume`, continues the run directory an arena that died left: telemetry.csv (its
  /// half-written last row dropped), retreats.csv, encounters.csv.
  /// @p scenario_yaml is the resolved scenario as its loader writes it (scenario::dump): the
  /// recorder itself reads no YAML, so that the in-memory core builds without yaml-cpp.
  RunRecorder(const std::string& dir, const scenario::Scenario& scenario, const std::string& scenario_yaml,
              bool resume = false);

  /// The file that shows @p dir holds a recorded run (its telemetry.csv or summary.json), or
  /// empty if it holds none.
  static std::string recorded_run_in(const std::string& dir);

  /// --resume: the tick of the last complete telemetry row (0 if none) and the journal.
  std::int64_t resumable_tick() const { return resumable_tick_; }
  const RetreatJournal& journal() const { return journal_; }

  /// Appends one telemetry row (every tick); with `write` false (a resumed arena replaying the
  /// ticks already on disk) only the summary's statistics are updated. Flushed at once unless
  /// flush_each_tick(false), so that a killed arena leaves every tick it stepped.
  void record_tick(const physics::Telemetry& telemetry, bool write = true);
  /// Whether record_tick flushes every row (default: yes, what --resume needs). A run that
  /// cannot be resumed (in process) turns it off: one write a tick would cost more than its
  /// world at small N. finish() flushes either way.
  void flush_each_tick(bool on) { flush_each_tick_ = on; }
  /// Journals a retreat decision applied at `tick` (flushed at once).
  void record_retreat(std::int64_t tick, std::uint32_t robot);
  /// One robot's record of the trajectory at @p tick (what TrajectoryHash::add hashes):
  /// transitions.csv gets a row when it differs from the robot's previous one (and for its
  /// first), so that retreat-diff can name the robot and field where two runs diverge.
  void record_state(std::int64_t tick, std::uint32_t robot, std::uint8_t phase, bool retreat);
  /// The tick's link of the hash chain (TrajectoryHash::link), appended to chain.bin.
  void record_link(std::int64_t tick, std::uint64_t link);
  /// Appends completed contact intervals (when arena.record_encounters).
  void record_contacts(const std::vector<physics::ContactRecord>& records);
  /// Writes agents.csv and summary.json and flushes everything.
  void finish(const physics::World& world, const std::vector<AgentRecord>& agents,
              const RunSummary& summary);

  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  scenario::Scenario scenario_;
  bool flush_each_tick_ = true;
  std::ofstream telemetry_;
  std::ofstream encounters_;
  std::ofstream retreats_;
  std::ofstream chain_;        ///< chain.bin: magic, then one link per tick from tick 0
  std::ofstream transitions_;  ///< transitions.csv
  std::vector<std::uint16_t> last_state_;  ///< by robot: phase | retreat << 8; 0xFFFF before its first
  std::vector<std::int64_t> retreat_started_;  ///< by robot: when it began retreating [tick]; −1: not
  std::uint64_t retreats_completed_ = 0;        ///< retreating robots that then departed
  std::int64_t longest_completed_retreat_ = 0;  ///< [ticks]
  std::int64_t next_link_tick_ = 0;
  std::int64_t resumable_tick_ = 0;
  RetreatJournal journal_;
  // population (inside) per tick for the summary's statistics
  std::vector<std::pair<double, std::uint32_t>> population_;
  physics::Telemetry last_{};
};

}  // namespace retreat::arena
