// retreat-agent: one robot's decision layer (Algorithm 1 of the paper), one process per robot.
//
// Reads:  <prefix>/robot_<id>/proximity   (its own robot's proximity frames, nothing else)
// Writes: <prefix>/robot_<id>/decision    (its own decision, one per accepted frame)
//         <prefix>/agent_status           (its own status, keyed by robot id)
//
// Exit codes: 0 after the robot departed or on SIGINT/SIGTERM; 2 bad input at start-up;
// 1 middleware failure.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <variant>

#include "retreat/agent/agent_node.hpp"
#include "retreat/agent/command_line.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/transport/factory.hpp"

int main(int argc, char** argv) {
  using namespace retreat;
  constexpr const char* program = "retreat-agent";
  const auto parsed =
      scenario::parse_or_report(program, [&] { return agent::parse_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& command_line = std::get<agent::AgentCommandLine>(parsed);
  const auto& s = command_line.scenario;
  const auto robot_id = command_line.robot_id;
  if (command_line.print_config) {
    std::cout << scenario::dump(s);
    return 0;
  }

  scenario::install_stop_handlers();
  try {
    const auto robot = "robot_" + std::to_string(robot_id);
    auto transport = transport::make_transport(
        retreat::name_of(s.dds.vendor), scenario::participant_options(s, "retreat-agent/" + robot,
                                                    agent::agent_user_data(robot_id), robot));
    agent::AgentNode node(s, robot_id, *transport);
    while (!scenario::stop_requested() && !node.departed()) {
      node.spin_once(std::chrono::milliseconds(100));
    }
    node.flush(std::chrono::seconds(1));
    const auto& c = node.counters();
    std::fprintf(stderr,
                 "retreat-agent robot %u: %s; frames %llu, dropped %llu, decisions %llu, "
                 "arena incarnations %u, retreated %s\n",
                 robot_id, node.departed() ? "departed" : "stopped",
                 static_cast<unsigned long long>(c.frames_received),
                 static_cast<unsigned long long>(c.frames_dropped),
                 static_cast<unsigned long long>(c.decisions_sent), c.arena_incarnations,
                 node.agent().retreating() ? "yes" : "no");
    scenario::limit_teardown(program, scenario::teardown_limit, 0);  // nothing left to send or record
    return 0;
  } catch (const std::invalid_argument& e) {
    scenario::report_error(program, e.what());
    return 2;
  } catch (const std::exception& e) {
    scenario::report_error(program, e.what());
    return 1;
  }
}
