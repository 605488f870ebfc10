#include "retreat/arena/command_line.hpp"

#include "retreat/scenario/program_options.hpp"

namespace retreat::arena {

std::variant<ArenaCommandLine, int> parse_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-arena";
  CLI::App app{"retreat-arena: the simulated world of a voluntary-retreat swarm over DDS"};
  scenario::CommonOptions common;
  ArenaCommandLine out;
  scenario::add_common_options(app, common);
  app.add_option("--out", out.out_dir, "run directory to write (telemetry, summary)");
  app.add_flag(
      "--resume", out.resume,
      "continue the run in --out DIR that a dead arena left, with the same agents (rebuilds "
      "the world from the scenario and DIR/retreats.csv, then goes on from its last tick)");
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<ArenaCommandLine, int> {
    out.scenario = scenario::load_scenario(common);
    if (out.resume && out.out_dir.empty()) {
      throw scenario::ConfigError("--resume needs --out DIR (the run directory to continue)");
    }
    out.print_config = common.print_config;
    return out;
  });
}

}  // namespace retreat::arena
