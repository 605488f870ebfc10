#pragma once
/// @file
/// What the bridge knows about a running swarm: the newest arena telemetry, poses and agent
/// statuses (a current snapshot), the distribution of the agents' current density estimates,
/// and a bounded time series of the run. Pure: std and retreat::wire only; time comes in with
/// the samples (simulated seconds), never from a clock.

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "retreat/wire/messages.hpp"

namespace retreat::telemetry {

/// Fixed facts of a run, from its scenario: what the numbers are compared against.
struct RunInfo {
  std::string scenario = "unnamed";
  std::string mode = "lockstep";    ///< `lockstep` or `realtime`
  std::string shape = "ellipse";    ///< domain shape: `ellipse` or `rectangle`
  double half_x = 1.0;              ///< half extent of D along x (semi-axis or width/2) [m]
  double half_y = 1.0;              ///< half extent of D along y [m]
  double area = 0.0;                ///< |D| [m²]
  double lambda_star = 0.0;         ///< optimal density λ* [robots/m²]
  std::string encounter_model = "physical";  ///< `physical` (poses carry positions) or `kinetic`
  double robot_radius = 0.055;      ///< footprint radius [m] (for drawing)
  double delta = 0.1;               ///< δ: contact within 2δ [m] (for drawing)
  std::uint32_t robots = 0;         ///< robots inside and waiting at the start
  double duration = 0.0;            ///< simulated run length [s]
  double status_period = 1.0;       ///< agents publish their status this often [simulated s]
  double telemetry_period = 0.1;    ///< the arena publishes this often [simulated s]
  /// Optimal population λ*·|D| [robots].
  double optimal_population() const { return lambda_star * area; }
};

/// How the aggregator bins and bounds what it keeps.
struct AggregatorOptions {
  /// Bins of the estimate histogram over [0, histogram_range_factor·λ*); values beyond fall
  /// into `overflow`.
  std::uint32_t histogram_bins = 12;
  double histogram_range_factor = 3.0;
  /// Most points the time series keeps; when a point would exceed it, every second point is
  /// dropped and the spacing between accepted points doubles. At least 4.
  std::size_t history_capacity = 2048;
  /// Least simulated time between two accepted points at the start [s] (0: every sample).
  double history_spacing = 0.0;
  /// An agent status older than this (simulated seconds behind the newest telemetry) no longer
  /// counts in the estimate distribution [s]. Non-positive: 3·status_period + 1.
  double stale_after = 0.0;
};

/// The distribution of the agents' current estimates λ̂_i [robots/m²].
struct EstimateHistogram {
  double bin_width = 0.0;              ///< [robots/m²]; bin k covers [k·w, (k+1)·w)
  std::vector<std::uint32_t> counts;   ///< one per bin
  std::uint32_t overflow = 0;          ///< estimates ≥ bins·w
  std::uint32_t count = 0;             ///< estimates counted (bins + overflow)
  double sum = 0.0;                    ///< their sum [robots/m²]
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  /// Mean estimate (NaN when none counted).
  double mean() const { return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN(); }
};

/// One agent as last heard from.
struct AgentView {
  wire::AgentStatus status;
  /// Its estimate counts in the distribution: deciding, not retreating, not stale, and (when
  /// the poses list robots; the kinetic world's do not) its robot is inside D.
  bool counted = false;
};

/// One point of the time series, taken from an arena telemetry sample.
struct HistoryPoint {
  double time = 0.0;  ///< simulated time [s]
  std::int64_t tick = 0;
  std::uint32_t inside = 0;
  std::uint32_t waiting = 0;
  std::uint32_t retreating = 0;
  std::uint32_t departed = 0;
  std::uint32_t lost_agents = 0;
  std::uint64_t deliveries = 0;
  double true_density = 0.0;      ///< [robots/m²]
  double ticks_per_second = 0.0;  ///< wall-clock rate of the arena loop
  std::uint32_t estimates = 0;    ///< agents counted in the estimate distribution then
  double lambda_hat_mean = std::numeric_limits<double>::quiet_NaN();  ///< [robots/m²]
  double lambda_hat_min = std::numeric_limits<double>::quiet_NaN();
  double lambda_hat_max = std::numeric_limits<double>::quiet_NaN();
};

/// Samples taken and ignored, per topic.
struct SampleCounters {
  std::uint64_t telemetry = 0;
  std::uint64_t poses = 0;
  std::uint64_t statuses = 0;
  /// Older than what is already known (a tick behind the newest of the same source): ignored.
  std::uint64_t stale = 0;
};

/// A copy of everything at one moment, for rendering.
struct Snapshot {
  RunInfo run;
  std::optional<wire::ArenaTelemetry> telemetry;
  std::optional<wire::Poses> poses;
  std::vector<AgentView> agents;  ///< ascending robot id
  EstimateHistogram estimates;
  SampleCounters samples;
  std::size_t history_size = 0;
  double history_spacing = 0.0;
  std::uint64_t history_compactions = 0;
  std::optional<HistoryPoint> last_point;  ///< newest point of the time series
  std::uint32_t runs = 0;        ///< runs seen (a telemetry clock going backwards starts a new one)
  std::uint64_t version = 0;     ///< grows with every accepted sample
};

/// Aggregates the three observation topics. Not thread-safe: one owner (the caller locks).
class Aggregator {
 public:
  /// @throws std::invalid_argument when an option is out of range (histogram_bins = 0,
  ///         history_capacity < 4, negative spacing or range).
  explicit Aggregator(RunInfo run, AggregatorOptions options = {});

  /// Newest arena telemetry. A sample whose time is earlier than the newest one's starts a new
  /// run: history, poses and agents are cleared. Appends a history point when the spacing
  /// allows it.
  void on_telemetry(const wire::ArenaTelemetry& t);
  /// Newest poses; older ticks than the newest are ignored (counted stale).
  void on_poses(const wire::Poses& p);
  /// One agent's status; an older tick than that agent's newest is ignored (counted stale).
  void on_status(const wire::AgentStatus& s);

  Snapshot snapshot() const;
  /// The time series, oldest first.
  const std::deque<HistoryPoint>& history() const { return history_; }
  /// The current estimate distribution.
  EstimateHistogram estimates() const;
  std::uint64_t version() const { return version_; }
  const RunInfo& run() const { return run_; }
  const AggregatorOptions& options() const { return options_; }

 private:
  bool counts(const wire::AgentStatus& s) const;
  void append_point(const wire::ArenaTelemetry& t);
  void reset_run();

  RunInfo run_;
  AggregatorOptions options_;
  double stale_after_ = 0.0;
  std::optional<wire::ArenaTelemetry> telemetry_;
  std::optional<wire::Poses> poses_;
  std::map<wire::RobotId, wire::Phase> pose_phase_;
  std::map<wire::RobotId, wire::AgentStatus> agents_;
  std::deque<HistoryPoint> history_;
  double spacing_ = 0.0;
  std::uint64_t compactions_ = 0;
  SampleCounters samples_;
  std::uint32_t runs_ = 0;
  std::uint64_t version_ = 0;
};

}  // namespace retreat::telemetry
