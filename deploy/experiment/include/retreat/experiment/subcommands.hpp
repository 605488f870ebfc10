#pragma once
/// @file
/// The subcommands of retreat-experiment. Each takes its options as parse_command_line() checked
/// them (command_line.hpp), writes its run directory (data as CSV and JSON, report.html with the
/// figures) and returns 0; a missing scenario file or a run directory in use throws UsageError, a
/// failed run RunFailure.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "retreat/experiment/common.hpp"

namespace retreat::experiment {

/// `encounters`: the paper's encounter-model validation (MODEL.md §6) in the physical world.
struct EncountersOptions {
  Common common;
  std::optional<std::uint64_t> seed;  ///< default: the scenario's
  std::optional<std::uint32_t> robots;  ///< default 200 (quick 60); the density is kept
  std::optional<double> duration;     ///< measured seconds after the warm-up; default 100 (quick 20)
};
int run_encounters(const EncountersOptions& options);

/// `throughput`: simulated T(λ)λ over a grid of λ against the CTMC curve.
struct ThroughputOptions {
  Common common;
  std::optional<SeedRange> seeds;       ///< world seeds, pooled per density; default the scenario's
  std::vector<double> lambdas;          ///< default 0.25 0.5 0.75 0.99 1.5 2 3 4 (quick 0.5 0.99 2)
  std::optional<std::uint32_t> robots;  ///< per density; default 200 (quick 40)
  std::optional<double> duration;       ///< measured seconds; default 2500 (quick 500)
};
int run_throughput(const ThroughputOptions& options);

/// `robotarium`: population against time over many seeds, in four set-ups.
struct RobotariumOptions {
  Common common;
  std::optional<SeedRange> seeds;          ///< in-process; default 1:100 (quick 1:3)
  std::optional<SeedRange> process_seeds;  ///< agent processes; default 1:5 (quick 1:2)
  bool no_processes = false;
  std::string dds = "fastdds";
  std::optional<int> domain;
  std::optional<double> process_duration;  ///< default the scenario's (quick 150 s)
};
int run_robotarium(const RobotariumOptions& options);

/// `controllers`: every registered controller (Common::controllers: or those asked for) against
/// `paper` on the same seeds and scenarios.
struct ControllersOptions {
  Common common;
  std::optional<SeedRange> seeds;  ///< default 1:100 (quick 1:3, and the endless queue 1,200 s)
};
int run_controllers(const ControllersOptions& options);

/// `noise`: every registered rule with imperfect proximity sensors (missed and false onsets).
struct NoiseOptions {
  Common common;
  std::optional<SeedRange> seeds;  ///< default 1:100 (quick 1:2, and the endless queue 300 s)
};

int run_noise(const NoiseOptions& options);

/// `sweep`: every registered rule on a grid of scenarios around the shipped ones.
struct SweepOptions {
  Common common;
  std::optional<SeedRange> seeds;  ///< default 1:100 (quick 1:2, and every run 300 s)
};

int run_sweep(const SweepOptions& options);

}  // namespace retreat::experiment
