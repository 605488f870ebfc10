#pragma once
/// @file
/// The launcher's command line, and the plan it resolves to once everything is validated.
/// Nothing here starts a process or writes a file.

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::launch {

/// Bad launcher input: one line naming the value and what is allowed (exit code 2).
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The command line as given.
struct LaunchOptions {
  std::string scenario_path;
  std::string dds;                     ///< empty: the scenario's dds.vendor
  std::optional<int> domain;           ///< empty: a free domain id in 1..99 (process mode)
  std::string out_dir;                 ///< empty: runs/<timestamp>
  std::optional<std::uint64_t> seed;   ///< overrides the scenario's seed
  std::string seeds;                   ///< "A:B", inclusive
  std::vector<std::string> overrides;  ///< section.key=value, passed on to every program
  bool no_bridge = false;
  bool in_process = false;
  std::string bin_dir;  ///< empty: the directory of this executable
  std::string arena_profile;  ///< the arena's dds.profile (the hub of a star); empty: dds.profile
  std::optional<unsigned> jobs;  ///< seeds run at once (--in-process); empty: the core count
  std::string record;  ///< --record FILE: retreat-record writes the run's DDS traffic there (MCAP)
};

using scenario::parse_seed_range;
using scenario::SeedRange;

/// Which vendor each process uses.
struct VendorPlan {
  std::string label;  ///< fastdds, cyclonedds, mixed (or inmemory in-process)
  std::string arena;  ///< the arena's vendor (and the launcher's telemetry reader's, the bridge's)
  /// The vendor of agent number `index` (0-based, in robot id order).
  std::string agent(std::uint32_t index) const;
};

/// Everything validated: what to run, and how.
struct Plan {
  LaunchOptions options;
  scenario::Scenario scenario;         ///< resolved with the overrides, the first seed, the domain
  std::vector<std::string> overrides;  ///< what children get with --set (user's + seed)
  std::vector<std::uint64_t> seeds;    ///< one run per seed
  bool multi_seed = false;             ///< --seeds: runs go to OUT/seed_<n>/
  VendorPlan vendors;
  bool endless = false;                ///< arena.queue = endless
  std::optional<int> domain;           ///< explicit domain (--domain or --set dds.domain=N)
  std::string arena_exe, agent_exe, bridge_exe;  ///< bridge_exe empty: none (or --no-bridge)
  /// retreat-agent-<vendor>, the agent with one DDS vendor linked, for each vendor whose program
  /// is beside agent_exe (started instead of agent_exe: cheaper to start, less memory).
  std::map<std::string, std::string> single_vendor_agent_exe;
  std::string record_exe;              ///< retreat-record, with --record; empty otherwise
  bool bridge_missing = false;         ///< no retreat-bridge next to the launcher
  unsigned jobs = 1;                   ///< seeds run at once (> 1 only in process)
};

/// The program an agent of @p vendor runs: retreat-agent-<vendor> when it was found beside
/// retreat-agent, else retreat-agent.
const std::string& agent_program(const Plan& plan, const std::string& vendor);

/// Validates the command line and the scenario with every override; throws UsageError or
/// scenario::ConfigError (both one line). Does not start anything or create any file.
/// `self_dir` is the directory of the launcher's executable.
Plan make_plan(const LaunchOptions& options, const std::string& self_dir);

/// Where --record writes the run of @p seed: FILE as given (absolute), or with several seeds
/// FILE with `.seed<n>` before its extension (`run.mcap` -> `run.seed3.mcap`). Empty: no --record.
std::string recording_path(const Plan& plan, std::uint64_t seed);

/// The overrides a child gets for one seed (the user's, then `seed=<n>`).
std::vector<std::string> overrides_for_seed(const Plan& plan, std::uint64_t seed);

}  // namespace retreat::launch
