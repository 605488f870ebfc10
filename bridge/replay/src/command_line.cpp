#include "retreat/replay/command_line.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/model/format_number.hpp"
#include "retreat/scenario/program_options.hpp"

namespace retreat::replay {

std::variant<ReplayCommandLine, int> parse_replay_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-replay";
  CLI::App app{"retreat-replay: plays a recording's proximity frames to live agents and compares their answers "
               "with the recorded ones; with --controller, re-decides the recorded inputs with another rule"};
  ReplayCommandLine out;
  std::string robots = "all";
  std::string pace = "lockstep";
  app.add_option("recording", out.recording, "the MCAP file retreat-record wrote")->required();
  app.add_option("--robots", robots, "the robots to replay: all, or ids separated by commas (0,3,7)");
  app.add_option("--dds", out.dds, "fastdds, cyclonedds or inmemory (agents in this process); default: the recording's");
  scenario::add_whole_number(app, "--domain", out.domain, "DDS domain id 0..232; default: the recording's", 0,
                             transport::max_domain_id);
  app.add_option("--pace", pace, "lockstep (as fast as the agents answer) or recorded (not faster than recorded)");
  app.add_option("--controller", out.options.controller,
                 "re-decide every tick with this registered rule and report where it differs");
  app.add_option("--set", out.options.agent_overrides,
                 "re-decide with another value of an agent parameter: agent.key=value (repeatable)");
  app.add_flag("--no-agents", [&](std::int64_t) { out.spawn_agents = false; },
               "start no agents: they are running already (a real robot's, say)");
  app.add_option("--answer-timeout", out.answer_timeout, "seconds an agent may take to answer one frame (default 60)");
  app.add_option("--report", out.report, "write the outcome as JSON to FILE");
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<ReplayCommandLine, int> {
    if (robots != "all") {
      std::size_t at = 0;
      while (at <= robots.size()) {
        const auto comma = std::min(robots.find(',', at), robots.size());
        const auto item = robots.substr(at, comma - at);
        std::uint32_t id = 0;
        const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), id);
        if (item.empty() || ec != std::errc() || end != item.data() + item.size()) {
          throw scenario::ConfigError("--robots '" + robots + "': must be all, or robot ids (0, 1, ...) separated by commas");
        }
        if (std::find(out.options.robots.begin(), out.options.robots.end(), id) != out.options.robots.end()) {
          throw scenario::ConfigError("--robots '" + robots + "': robot " + std::to_string(id) + " is named twice");
        }
        out.options.robots.push_back(id);
        at = comma + 1;
      }
    }
    if (pace == "lockstep") {
      out.options.pace = Pace::lockstep;
    } else if (pace == "recorded") {
      out.options.pace = Pace::recorded;
    } else {
      throw scenario::ConfigError("--pace '" + pace + "': must be lockstep or recorded");
    }
    if (!out.options.controller.empty() && !agent::is_controller_name(out.options.controller)) {
      std::string names;
      for (const auto& n : agent::controller_names()) names += (names.empty() ? "" : ", ") + n;
      throw scenario::ConfigError("--controller '" + out.options.controller + "': must be one of " + names);
    }
    for (const auto& o : out.options.agent_overrides) {
      if (o.rfind("agent.", 0) != 0 || o.find('=') == std::string::npos) {
        throw scenario::ConfigError("--set '" + o + "': a replay changes the agents' parameters only (agent.key=value)");
      }
    }
    if (out.options.redecide() && out.options.pace == Pace::recorded) {
      throw scenario::ConfigError("--pace recorded with --controller or --set: a re-decision sends every tick, which "
                                  "was not recorded; use --pace lockstep");
    }
    if (!out.dds.empty() && out.dds != "fastdds" && out.dds != "cyclonedds" && out.dds != "inmemory") {
      throw scenario::ConfigError("--dds '" + out.dds + "': must be fastdds, cyclonedds or inmemory");
    }
    if (out.dds == "inmemory" && !out.spawn_agents) {
      throw scenario::ConfigError("--no-agents with --dds inmemory: agents in this process are started by it");
    }
    if (!std::isfinite(out.answer_timeout) || out.answer_timeout <= 0.0 || out.answer_timeout > 86400.0) {
      throw scenario::ConfigError("--answer-timeout " + model::format_number(out.answer_timeout) +
                                  ": must be more than 0 and at most 86400 seconds");
    }
    return out;
  });
}

std::variant<DiffCommandLine, int> parse_diff_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-diff";
  CLI::App app{"retreat-diff: the first tick, robot and field where two runs diverge (run directories or "
               "recordings), or that they are identical"};
  DiffCommandLine out;
  app.add_option("a", out.a, "a run directory (retreat-launch --out, retreat-arena --out) or a recording (.mcap)")
      ->required();
  app.add_option("b", out.b, "the other, of the same kind")->required();
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return out;
}

}  // namespace retreat::replay
