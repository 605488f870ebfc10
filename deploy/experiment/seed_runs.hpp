#pragma once
/// @file
/// What the experiments take from one launcher run directory (OUT/seed_<n>/telemetry.csv and
/// summary.json): the population on a time grid, and the cost J of MODEL.md §4 over two spans.

#include <cstdint>
#include <string>
#include <vector>

namespace retreat::experiment {

/// The measured cost over the span [from, to] of a run:
///   λ̄ = time-mean of the robots inside D / |D| [robots/m²],
///   output = deliveries in the span / (|D| · (to − from)) [deliveries/(m²·s)],
///   J = C / output + λ̄ (MODEL.md §4 with T(λ)λ replaced by the measured output; +∞ without
///   any delivery).
struct SpanCost {
  double from = 0.0;  ///< [s]
  double to = 0.0;    ///< [s]
  double mean_population = 0.0;  ///< time-mean of `inside` [robots]
  double deliveries = 0.0;
  double lambda = 0.0;  ///< λ̄ [robots/m²]
  double output = 0.0;  ///< [deliveries/(m²·s)]
  double J = 0.0;       // NOLINT(readability-identifier-naming): the paper's symbol
};

/// One seed's run, reduced.
struct SeedRun {
  std::uint64_t seed = 0;
  std::string dir;
  double duration = 0.0;          ///< simulated seconds [s]
  double area = 0.0;              ///< |D| [m²]
  double optimal_population = 0.0;  ///< λ*·|D| [robots]
  double final_population = 0.0;    ///< robots inside at the end
  double mean_last_300s = 0.0;      ///< time-mean of `inside` over the last 300 s
  double departed = 0.0;            ///< robots that had left D by the end
  double retreating_at_end = 0.0;   ///< robots still driving out at the end
  /// How long the longest-running of them had been driving out by the end (summary.json's
  /// retreats.longest_under_way_seconds; 0 when none) [s].
  double longest_retreat_under_way = 0.0;
  std::uint32_t agents_lost = 0;
  std::string trajectory_sha256;  ///< the arena's hash of every decision (same seed, same hash)
  SpanCost whole;      ///< [0, duration]
  SpanCost last_half;  ///< [duration/2, duration]
  std::vector<double> population;  ///< `inside` at grid_step · k, k = 0 .. duration/grid_step
};

/// Reads every OUT/seed_<n>/ the launcher wrote (ascending seed). `C` is the cost weight;
/// `grid_step` the spacing of SeedRun::population [s]. Throws RunFailure when a seed directory
/// lacks telemetry.csv or summary.json, or they do not parse. Up to `jobs` directories are read
/// at once; the result is the same whatever `jobs` is.
std::vector<SeedRun> read_seed_runs(const std::string& launch_out, double C, double grid_step, unsigned jobs = 1);

}  // namespace retreat::experiment
