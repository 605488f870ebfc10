#pragma once
/// @file
/// What the launcher adds to a run directory's summary.json (written by the arena), and the
/// aggregate of several seeds (seeds_summary.json). Files are replaced atomically.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace retreat::launch {

/// How one run was launched.
struct LaunchRecord {
  std::string dds;             ///< fastdds, cyclonedds, mixed, inmemory
  std::string mode;            ///< processes or in-process
  std::uint32_t agents_started = 0;  ///< agent processes (or in-process agent nodes) started
  double wall_seconds = 0.0;   ///< the whole launch of this run: start-up, run, shutdown
  int domain = -1;             ///< DDS domain id (-1 in-process)
  std::string arena_vendor;
  std::map<std::string, std::uint32_t> agent_vendors;  ///< vendor -> agent processes
  bool bridge = false;
  std::uint32_t bridge_restarts = 0;  ///< times the launcher restarted a bridge that died
  std::uint32_t arena_restarts = 0;   ///< times it resumed an arena killed by a signal
  /// From the launch until the launcher saw the arena's first telemetry (tick 0, published once
  /// the agents matched) [s]; −1: not seen (in-process, or no telemetry reader).
  double seconds_to_first_tick = -1.0;
  /// CPU time [s] of the arena, the agents and the recorder, which the launcher has reaped when
  /// it writes the summary (getrusage(RUSAGE_CHILDREN): exact, not sampled; not the bridge,
  /// stopped after it, nor the launcher); −1 in-process.
  double children_user_seconds = -1.0;
  double children_system_seconds = -1.0;
  std::string recording;         ///< --record: the MCAP file; empty: none
  std::string recorder_exit;     ///< how retreat-record ended ("exit code 0", ...)
};

/// Writes `j` to `path` through a temporary file and rename(): readers never see half a file.
void write_json_atomically(const std::string& path, const nlohmann::json& j);

/// Reads `dir`/summary.json, adds the launch record, writes it back atomically and returns it.
/// Throws std::runtime_error when the arena left no readable summary.
nlohmann::json update_summary(const std::string& dir, const LaunchRecord& record);

/// Writes `out_dir`/seeds_summary.json from each seed's summary.
nlohmann::json write_seeds_summary(const std::string& out_dir,
                                   const std::vector<nlohmann::json>& summaries);

}  // namespace retreat::launch
