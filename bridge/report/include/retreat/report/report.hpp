#pragma once
/// @file
/// report.html: one self-contained page (uPlot, its CSS and the page script inlined; no network)
/// with the plots of a run directory, or of a directory of seed_<n>/ run directories:
///   - population over time against the optimum λ*·|D| (mean and min–max band over seeds);
///   - throughput (deliveries per second in windows of max(run/30, 20 s)) against the CTMC
///     curve T(λ)·λ·|D| at the window's mean population;
///   - inter-encounter times against the exponential (when encounters.csv exists): the model's
///     Ω_c at the run's mean density and the fitted rate;
///   - the agents' estimates over time (when the bridge recorded agent_status.csv) against λ*
///     and the true density;
///   - a table of each run's summary.json.

#include <string>

#include <nlohmann/json.hpp>

namespace retreat::report {

/// The numbers the report plots, as JSON (what the page script receives):
/// {"title", "runs": [summary...], "run_dirs": [...], "lambda_star", "area", "optimum",
///  "population": {"time", "mean", "min", "max", "seeds"}, "throughput": {"window", "points":
///  [[N, rate]...], "curve": [[N, rate]...]}, "encounters": null (no encounters.csv) | {"gaps", "bins":
///  null (fewer than 2 gaps) | [[centre, density]...], "bin_width", "mean_gap", "fitted_rate",
///  "model_rate", "mean_density"},
///  "estimates": null | {"time", "mean", "low", "high", "true_density", "agents"}}
/// @throws std::runtime_error when `dir` holds no telemetry.csv, neither itself nor in seed_*
///         directories; scenario::ConfigError for a bad scenario.yaml.
nlohmann::json report_data(const std::string& dir);

/// The report page for `dir` (see report_data).
std::string render_report(const std::string& dir);

/// Writes render_report(dir) to `path` (default `dir/report.html`) through a temporary file,
/// so that a reader never sees half a report. Returns the path written.
std::string write_report(const std::string& dir, const std::string& path = {});

}  // namespace retreat::report
