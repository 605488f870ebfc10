#pragma once
/// @file
/// retreat-diff's work: where two runs diverge. Two run directories are compared by their
/// per-tick hash chains (chain.bin: link k is the trajectory hash of the run cut after tick k),
/// which give the first tick whose (robot, phase, decision) records differ; their transitions
/// (transitions.csv) then name the robot and the field, and their telemetry (telemetry.csv) the
/// first tick whose counts differ. Two recordings are compared message by message: every robot's
/// frames and answers, the agents' statuses, the arena's poses and telemetry, tick by tick.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace retreat::replay {

/// Input that cannot be compared (a missing file, not a run directory, a corrupted recording,
/// a run directory against a recording); one line.
class DiffError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct DiffResult {
  bool identical = false;
  std::int64_t tick = -1;  ///< the first tick where they differ (-1: identical)
  std::string robot;       ///< the robot whose record differs there ("" for the arena's counts)
  std::string field;       ///< the field that differs
  std::string a, b;        ///< its values in A and B
  std::string report;      ///< what to print: one line first, details after
};

/// Compares two run directories (chain.bin, transitions.csv, telemetry.csv).
DiffResult diff_run_directories(const std::string& a, const std::string& b);

/// Compares two recordings (retreat-record's MCAP files).
DiffResult diff_recordings(const std::string& a, const std::string& b);

/// Either, by what @p a and @p b are (directories or files; both the same kind).
DiffResult diff_runs(const std::string& a, const std::string& b);

}  // namespace retreat::replay
