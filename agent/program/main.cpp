// retreat-agent: one robot's decision layer (Algorithm 1 of the paper), one process per robot.
//
// Reads:  <prefix>/robot_<id>/proximity   (its own robot's proximity frames, nothing else)
// Writes: <prefix>/robot_<id>/decision    (its own decision, one per accepted frame)
//         <prefix>/agent_status           (its own status, keyed by robot id)
//
// Exit codes: 0 after the robot departed or on SIGINT/SIGTERM; 2 bad input at start-up;
// 1 middleware failure.

#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "agent_node.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/transport/factory.hpp"

namespace {

std::atomic<bool> stop_requested{false};
extern "C" void on_signal(int) { stop_requested.store(true); }

}  // namespace

int main(int argc, char** argv) {
  using namespace retreat;
  CLI::App app{"retreat-agent: one robot's voluntary-retreat decision layer over DDS"};
  std::uint32_t robot_id = 0;
  std::string scenario_path, dds;
  int domain = -1;
  std::vector<std::string> overrides;
  bool print_config = false;
  app.add_option("--robot-id", robot_id, "the robot this agent serves")->required();
  app.add_option("--scenario", scenario_path, "scenario file (YAML)")->required();
  app.add_option("--dds", dds, "middleware: fastdds or cyclonedds (overrides dds.vendor)");
  app.add_option("--domain", domain, "DDS domain id 0..232 (overrides dds.domain)");
  app.add_option("--set", overrides, "override a scenario value: section.key=value")->allow_extra_args(false);
  app.add_flag("--print-config", print_config, "print the resolved scenario and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "retreat-agent: %s\n", e.what());
    return 2;
  }

  scenario::Scenario s;
  try {
    if (!dds.empty()) overrides.push_back("dds.vendor=" + dds);
    if (domain != -1) overrides.push_back("dds.domain=" + std::to_string(domain));
    s = scenario::load(scenario_path, overrides);
    if (!scenario::has_robot(s, robot_id)) {
      const auto n = s.arena.robots_inside + s.arena.robots_waiting;
      throw scenario::ConfigError("--robot-id " + std::to_string(robot_id) +
                                  ": the scenario has robots 0.." + std::to_string(n - 1));
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "retreat-agent: %s\n", e.what());
    return 2;
  }
  if (print_config) {
    std::cout << scenario::dump(s);
    return 0;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    transport::ParticipantOptions options;
    options.domain_id = s.dds.domain;
    options.name = "retreat-agent/robot_" + std::to_string(robot_id);
    options.user_data = agent::agent_user_data(robot_id);
    options.profile = s.dds.profile;
    auto transport = transport::make_transport(s.dds.vendor, options);
    agent::AgentNode node(s, robot_id, *transport);
    while (!stop_requested.load() && !node.departed()) {
      node.spin_once(std::chrono::milliseconds(100));
    }
    node.flush(std::chrono::seconds(1));
    const auto& c = node.counters();
    std::fprintf(stderr,
                 "retreat-agent robot %u: %s; frames %llu, dropped %llu, decisions %llu, retreated %s\n",
                 robot_id, node.departed() ? "departed" : "stopped",
                 static_cast<unsigned long long>(c.frames_received),
                 static_cast<unsigned long long>(c.frames_dropped),
                 static_cast<unsigned long long>(c.decisions_sent),
                 node.agent().retreating() ? "yes" : "no");
    return 0;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "retreat-agent: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-agent: %s\n", e.what());
    return 1;
  }
}
