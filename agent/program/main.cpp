// retreat-agent: one robot's decision layer (Algorithm 1 of the paper), one process per robot.
//
// Reads:  <prefix>/robot_<id>/proximity   (its own robot's proximity frames, nothing else)
// Writes: <prefix>/robot_<id>/decision    (its own decision, one per accepted frame)
//         <prefix>/agent_status           (its own status, keyed by robot id)
//
// Exit codes: 0 after the robot departed or on SIGINT/SIGTERM; 2 bad input at start-up;
// 1 middleware failure; 3 no arena or robot driver appeared within run.startup_timeout.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <variant>

#include "retreat/agent/agent_node.hpp"
#include "retreat/agent/command_line.hpp"
#include "retreat/model/format_number.hpp"
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
        retreat::name_of(s.dds.vendor),
        scenario::robot_participant_options(s, robot_id, "retreat-agent/" + robot, agent::agent_user_data(robot_id), robot));
    agent::AgentNode node(s, robot_id, *transport, command_line.journal);
    if (node.counters().frames_recovered > 0) {
      std::fprintf(stderr, "retreat-agent robot %u: resumed from the journal '%s': %llu frames, up to tick %lld\n",
                   robot_id, command_line.journal.c_str(),
                   static_cast<unsigned long long>(node.counters().frames_recovered),
                   static_cast<long long>(node.agent().status().tick.value_or(-1)));
    }
    const auto started = std::chrono::steady_clock::now();
    const auto startup_timeout = std::chrono::duration<double>(s.run.startup_timeout);
    // Woken by a frame or a stop signal, not by polling: an idle agent costs its host nothing
    // (docs/benchmarks.md, "Lockstep swarm"). The second is only a ceiling for the start-up check.
    const scenario::StopWakeup stop_wakeup([&transport] { transport->wake(); });
    while (!scenario::stop_requested() && !node.departed()) {
      node.spin_once(std::chrono::seconds(1));
      if (!node.arena_seen() && std::chrono::steady_clock::now() - started > startup_timeout) {
        scenario::report_error(program, "robot " + std::to_string(robot_id) +
                                            ": no arena or robot driver appeared within run.startup_timeout = " +
                                            model::format_number(s.run.startup_timeout) + " s");
        scenario::limit_teardown(program, scenario::teardown_limit, 3);
        return 3;
      }
    }
    node.flush(std::chrono::seconds(3));  // well inside retreat-launch's 5 s stop grace
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
