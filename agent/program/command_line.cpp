#include "retreat/agent/command_line.hpp"

#include <cstdint>
#include <limits>
#include <string>

#include "retreat/scenario/program_options.hpp"

namespace retreat::agent {

std::variant<AgentCommandLine, int> parse_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-agent";
  CLI::App app{"retreat-agent: one robot's voluntary-retreat decision layer over DDS"};
  scenario::CommonOptions common;
  AgentCommandLine out;
  scenario::add_whole_number(app, "--robot-id", out.robot_id, "the robot this agent serves", std::uint32_t{0},
                             std::numeric_limits<std::uint32_t>::max())
      ->required();
  app.add_option("--journal", out.journal,
                 "journal every accepted frame to FILE; a restarted agent given the same FILE resumes "
                 "its window, steps and coins where the previous process stopped");
  scenario::add_common_options(app, common);
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<AgentCommandLine, int> {
    out.scenario = scenario::load_scenario(common);
    if (!scenario::has_robot(out.scenario, out.robot_id)) {
      const auto n = out.scenario.arena.robots_inside + out.scenario.arena.robots_waiting;
      throw scenario::ConfigError("--robot-id " + std::to_string(out.robot_id) +
                                  ": the scenario has robots 0.." + std::to_string(n - 1));
    }
    out.print_config = common.print_config;
    return out;
  });
}

}  // namespace retreat::agent
