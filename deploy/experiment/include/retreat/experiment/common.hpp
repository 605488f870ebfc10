#pragma once
/// @file
/// What every retreat-experiment subcommand shares: its options, seed ranges, the scenario
/// files, the run directory and its files (CSV, JSON, report.html).

#include <cstdint>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/scenario/program_options.hpp"

namespace retreat::experiment {

/// Bad input: one line naming the value and what is allowed (exit code 2).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A run that failed (a child failed, or left no data): exit code 1.
class RunFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using scenario::parse_seed_range;
using scenario::SeedRange;

/// The options every subcommand takes.
struct Common {
  std::string out_dir;        ///< the run directory (created; must not hold a previous run)
  bool quick = false;         ///< the reduced size (tests, smoke runs)
  std::string scenarios_dir;  ///< where the shipped scenario files are
  std::string launcher;       ///< retreat-launch (robotarium, controllers)
  std::optional<unsigned> jobs;  ///< in-process seeds run at once (retreat-launch --jobs); empty:
                                 ///< the launcher's default, the core count
  std::vector<std::string> controllers;  ///< --controllers (controllers, noise, sweep): the rules
                                         ///< asked for, registered names; empty: every one
  std::vector<std::string> overrides;    ///< --set (controllers, noise, sweep): `section.key=value`
                                         ///< on every run, before the subcommand's own
};

/// ", scenarios with --set a=b, c=d" for the overrides every run had (Common::overrides), or "".
std::string with_overrides(const std::vector<std::string>& overrides);

/// The threads the experiment's own work uses (reading runs, predictions): `jobs` (--jobs), or
/// the core count when it is not given (the launcher's default too).
unsigned worker_count(std::optional<unsigned> jobs);

/// Calls `fn(i)` once for every i in [0, n), on up to `jobs` threads (the calling one among
/// them), the indices taken in ascending order. The first exception any call throws is
/// rethrown once every thread has stopped (the indices not yet begun are skipped).
void for_each_index(std::size_t n, unsigned jobs, const std::function<void(std::size_t)>& fn);

/// The rules a comparison runs: `paper` first (every comparison is against it), then the ones
/// @p common asks for in the registry's order, or every registered rule when it asks for none.
std::vector<std::string> compared_controllers(const Common& common);

/// Checks --controllers (CLI11 splits it at commas): registered names, each at most once.
/// @throws UsageError naming the value and the registered names.
void check_controllers(const std::vector<std::string>& names);

/// `name` (e.g. "robotarium-2019.yaml") in the scenarios directory; throws UsageError when it
/// is not there.
std::string scenario_file(const Common& common, const std::string& name);

/// A shipped scenario the controllers are compared on: the paper's finite queue
/// (robotarium-2019.yaml) or the endless one (steady-influx.yaml).
struct QueueCase {
  std::string name;   ///< `finite` or `endless`
  std::string label;  ///< for people, e.g. `finite queue (robotarium-2019)`
  std::string file;   ///< the scenario file (scenario_file())
};

/// The finite queue, then the endless one; throws UsageError when a file is missing.
std::vector<QueueCase> queue_cases(const Common& common);

/// Creates the run directory; throws UsageError when it exists and is not empty (a previous
/// run is never mixed with a new one) or cannot be created.
void make_run_dir(const std::string& dir);

/// Writes JSON (2-space indent) through a temporary file. Non-finite numbers become null.
void write_json(const std::string& path, const nlohmann::json& j);

/// Writes `text` (e.g. results.md) through a temporary file, as write_json.
void write_text(const std::string& path, const std::string& text);

/// A CSV file: a header, then one row per call; numbers with 9 significant digits.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const std::vector<std::string>& header);
  ~CsvWriter();
  CsvWriter(const CsvWriter&) = delete;
  CsvWriter& operator=(const CsvWriter&) = delete;
  /// One row: each cell a number (NaN written as empty) or a string (no commas).
  void row(const std::vector<nlohmann::json>& cells);
  void close();  ///< flushes; throws RunFailure when the file could not be written

 private:
  std::string path_;
  std::size_t columns_;
  std::FILE* file_ = nullptr;
};

/// A number for a table: `digits` decimals, "–" when not finite.
std::string fixed(double value, int digits);

/// A JSON number, or null when not finite (JSON has no NaN or infinity).
nlohmann::json finite_or_null(double value);

/// Rounds to 6 significant digits (figures are for the eye; keeps report.html small).
double round6(double value);

}  // namespace retreat::experiment
