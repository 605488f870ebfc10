// retreat-arena: the physical world (or the kinetic one) of a voluntary-retreat run.
//
// Reads:  <prefix>/robot_<id>/decision     (each robot's decision, from its own agent)
// Writes: <prefix>/robot_<id>/proximity    (each robot's proximity frames, on its own topic)
//         <prefix>/arena_telemetry         (ground truth, keyed by arena id)
//         <prefix>/poses                   (positions for display, keyed by arena id)
// Files (--out DIR): scenario.yaml, telemetry.csv, agents.csv, encounters.csv (when asked),
//                    retreats.csv (the retreat decisions applied, by tick), summary.json.
//                    --resume continues such a directory after the arena died (lockstep or
//                    real time; in lockstep with the uninterrupted trajectory).
//
// Exit codes: 0 run completed (or stopped by SIGINT/SIGTERM, summary written); 2 bad input at
// start-up; 1 middleware or file failure.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <thread>
#include <variant>

#include "retreat/arena/arena_node.hpp"
#include "retreat/arena/command_line.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"

int main(int argc, char** argv) {
  using namespace retreat;
  using Clock = std::chrono::steady_clock;
  constexpr const char* program = "retreat-arena";
  const auto parsed =
      scenario::parse_or_report(program, [&] { return arena::parse_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& command_line = std::get<arena::ArenaCommandLine>(parsed);
  const auto& s = command_line.scenario;
  const auto& out_dir = command_line.out_dir;
  const bool resume = command_line.resume;
  if (command_line.print_config) {
    std::cout << scenario::dump(s);
    return 0;
  }
  scenario::install_stop_handlers();
  try {
    std::unique_ptr<arena::RunRecorder> recorder;
    if (!out_dir.empty()) recorder = std::make_unique<arena::RunRecorder>(out_dir, s, scenario::dump(s), resume);
    auto transport = transport::make_transport(
        retreat::name_of(s.dds.vendor), scenario::participant_options(s, "retreat-arena", wire::arena_user_data, "arena"));
    arena::ArenaNode node(s, *transport, recorder.get());
    if (resume) {
      node.replay(recorder->resumable_tick(), recorder->journal());
      std::fprintf(stderr, "retreat-arena: resumed %s at tick %lld\n", out_dir.c_str(),
                   static_cast<long long>(node.tick()));
    }
    const auto keep_going = [] { return !scenario::stop_requested(); };
    const bool lockstep = s.run.mode == scenario::RunMode::lockstep;

    const auto matched = node.wait_for_agents(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                  std::chrono::duration<double>(s.run.startup_timeout)),
                                              keep_going);
    std::fprintf(stderr, "retreat-arena: %u agents matched, running %s\n", matched,
                 std::string(retreat::name_of(s.run.mode)).c_str());
    const auto start = Clock::now();
    const auto period = std::chrono::duration<double>(s.agent.dt / s.run.speed);
    auto next = start;
    while (keep_going()) {
      node.publish_tick();
      if (lockstep) {
        if (!node.collect_lockstep(keep_going)) break;
      } else {
        next += std::chrono::duration_cast<Clock::duration>(period);
        std::this_thread::sleep_until(next);
        node.collect_available();
      }
      if (node.finished()) break;
      node.step();
    }
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    const auto summary = node.finish(wall);
    if (s.run.recorders > 0 && !node.flush(std::chrono::seconds(5))) {
      // A sample lost on the way is repaired only while the writer lives: with a recorder, the
      // arena leaves once every reader has what it wrote (or after 5 s).
      std::fprintf(stderr, "retreat-arena: not every reader acknowledged the last samples within 5 s; "
                           "a recording may miss them\n");
    }
    std::fprintf(stderr,
                 "retreat-arena: %lld ticks in %.2f s (%.0f ticks/s), %u agents lost, "
                 "%llu decisions dropped, trajectory %s\n",
                 static_cast<long long>(summary.ticks), wall,
                 wall > 0 ? static_cast<double>(summary.ticks) / wall : 0.0, summary.agents_lost,
                 static_cast<unsigned long long>(summary.decisions_dropped),
                 summary.trajectory_sha256.c_str());
    // The run directory is complete: a DDS teardown that hangs must not hold the run up.
    scenario::limit_teardown(program, scenario::teardown_limit, 0);
    return 0;
  } catch (const std::invalid_argument& e) {
    scenario::report_error(program, e.what());
    return 2;
  } catch (const std::exception& e) {
    scenario::report_error(program, e.what());
    return 1;
  }
}
