#include "retreat/launch/command_line.hpp"

#include <cstdint>
#include <limits>

#include "retreat/scenario/program_options.hpp"

namespace retreat::launch {

std::variant<LaunchCommandLine, int> parse_command_line(int argc, char** argv,
                                                        const std::string& self_dir) {
  constexpr const char* program = "retreat-launch";
  CLI::App app{
      "retreat-launch: runs a voluntary-retreat swarm (arena, one agent process per "
      "robot, bridge) on this machine, or in one process"};
  scenario::CommonOptions common;  // SCENARIO --dds --domain --set --print-config
  scenario::add_common_options(app, common, /*positional_scenario=*/true);
  app.get_option("--dds")->description(
      "fastdds, cyclonedds, or mixed (agents alternate vendors, the arena uses cyclonedds); "
      "default: the scenario's dds.vendor");
  app.get_option("--domain")->description("DDS domain id 0..232 (default: a free one in 1..99)");
  LaunchOptions o;
  std::uint64_t seed = 0;
  app.add_option("--out", o.out_dir, "run directory (default: runs/<timestamp>)");
  auto* seed_opt = scenario::add_whole_number(app, "--seed", seed, "scenario seed (overrides the file's)",
                                              std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max());
  app.add_option("--seeds", o.seeds, "run seeds A:B (inclusive, e.g. 1:100) into OUT/seed_<n>/");
  app.add_flag("--no-bridge", o.no_bridge, "do not start retreat-bridge");
  app.add_flag("--in-process", o.in_process,
               "arena and agents in this process over the in-memory transport (lockstep)");
  app.add_option("--arena-profile", o.arena_profile,
                 "DDS profile for the arena only, the hub of a star (deploy/dds/*-hub.xml); every "
                 "other process uses dds.profile");
  app.add_option("--record", o.record,
                 "record the run's DDS traffic into this MCAP file with retreat-record (with "
                 "--seeds: FILE.seed<n>.mcap); every process waits for the recorder before tick 0");
  unsigned jobs = 0;
  auto* jobs_opt = scenario::add_whole_number(
      app, "--jobs", jobs,
      "with --in-process and --seeds: seeds run at once, one thread each, 1..256 (default: the core "
      "count, or fewer if the host's memory holds fewer); the runs are the same as one after another",
      1u, scenario::max_jobs);
  app.add_option("--bin-dir", o.bin_dir,
                 "where retreat-arena, retreat-agent and retreat-bridge "
                 "are (default: next to retreat-launch)");
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  o.scenario_path = common.scenario_path;
  o.dds = common.dds;
  o.overrides = common.overrides;
  if (app.count("--domain") > 0) o.domain = common.domain;
  if (seed_opt->count() > 0) o.seed = seed;
  if (jobs_opt->count() > 0) o.jobs = jobs;
  // Everything is validated before anything is started or written.
  return scenario::guarded(program, [&]() -> std::variant<LaunchCommandLine, int> {
    return LaunchCommandLine{make_plan(o, self_dir), common.print_config};
  });
}

}  // namespace retreat::launch
