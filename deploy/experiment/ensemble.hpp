#pragma once
/// @file
/// Many seeds of one set-up, run by retreat-launch and reduced: the population over time
/// (mean, standard deviation, extremes over seeds) and per-seed results.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "launch.hpp"
#include "seed_runs.hpp"
#include "stats.hpp"

namespace retreat::experiment {

/// Grid of the population traces [s]: 1,200 s runs give 241 points, an hour 721.
inline constexpr double population_grid = 5.0;

/// One set-up over its seeds.
struct Ensemble {
  std::string name;   ///< file-name friendly, e.g. `finite-in-process`
  std::string label;  ///< for people, e.g. `finite queue, in-process`
  std::vector<SeedRun> runs;
  std::vector<double> time, mean, sd, min, max;  ///< population over seeds on the grid
};

/// Runs `request` with retreat-launch (output in request.out) and reduces its seeds with the
/// cost weight `C` (MODEL.md §4).
Ensemble run_ensemble(const std::string& launcher, const std::string& name, const std::string& label,
                      const LaunchRequest& request, double C);

/// J of the seeds pooled, over the whole run or its last half: C over the mean output, plus the
/// mean λ̄ (MODEL.md §4); +∞ when no seed delivered anything in the span.
double pooled_J(const Ensemble& e, double C, bool last_half);

/// A retreat still under way at the end after this long is stalled [s]. No point of the shipped
/// or swept domains is more than 1 m from their boundary (the 3.2 m × 2.0 m rectangle; the
/// shipped ellipse's semi-minor axis is 0.8 m), so a robot driving out unhindered at v = 0.1 m/s
/// is out within (1 + 0.055) / 0.1 ≈ 11 s; with the others in its way, 99 % of the retreats that
/// ended took under 22 s in every row of the full controllers run (docs/experiments.md,
/// "Retreats that never end"). A minute is well past both.
inline constexpr double stalled_retreat_after = 60.0;

/// The seeds of `e` that ended with a retreat under way for longer than stalled_retreat_after:
/// robots jammed under the barrier certificates.
std::size_t stalled_seeds(const Ensemble& e);

/// Statistics over seeds of one per-seed number.
Moments over_seeds(const Ensemble& e, double (*value)(const SeedRun&));

/// A figure: the population's mean and mean ± sd band over seeds against λ*·|D|.
nlohmann::json population_figure(const Ensemble& e, const std::string& id, const std::string& title);

/// Removes each seed's per-tick files (telemetry.csv, chain.bin, transitions.csv) once the
/// ensemble has been read from them: a sweep of many runs keeps its summaries, not its ticks.
void drop_per_tick_files(const Ensemble& e);

/// Appends the population traces of `e` to a CSV (ensemble, time, mean, sd, min, max).
void write_population_rows(CsvWriter& csv, const Ensemble& e);

}  // namespace retreat::experiment
