// retreat-record: records a swarm's DDS traffic into an MCAP file (docs/recording.md).
//
// Reads:  every topic of the swarm, raw: <prefix>/robot_<id>/{proximity,decision,plan,tracked_pose}
//         for robots 0..N-1 of the scenario and for every agent that appears in discovery (and
//         a few ids beyond), <prefix>/arena_telemetry, <prefix>/poses, <prefix>/agent_status.
// Writes: --out FILE (MCAP: one channel per topic, the IDL text as schema, the CDR bytes as they
//         travelled, zstd chunks, metadata "retreat" and, at the end, "retreat.recorder").
//         Announces itself as "retreat:recorder": with run.recorders: n the arena and the agents
//         wait for it before their robot's traffic begins.
//
// Exit codes: 0 stopped by SIGINT/SIGTERM, file complete, nothing dropped; 4 the same but the
// recorder fell behind and dropped samples (counted on stderr and in the file); 2 bad input at
// start-up; 1 middleware or file failure.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "retreat/recorder/command_line.hpp"
#include "retreat/recorder/recorder.hpp"
#include "retreat/scenario/json.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"

#ifndef RETREAT_PROJECT_VERSION
#error "RETREAT_PROJECT_VERSION must be defined by the build"
#endif

namespace {

using namespace retreat;
constexpr const char* program = "retreat-record";

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed =
      scenario::parse_or_report(program, [&] { return recorder::parse_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& command_line = std::get<recorder::RecordCommandLine>(parsed);
  const auto& s = command_line.scenario;
  if (command_line.print_config) {
    std::cout << scenario::dump(s);
    return 0;
  }
  scenario::install_stop_handlers();
  try {
    const std::string vendor(retreat::name_of(s.dds.vendor));
    std::optional<recording::McapWriter> opened;
    try {
      opened.emplace(command_line.out);
    } catch (const std::runtime_error& e) {
      scenario::report_error(program, std::string("--out: ") + e.what());
      return 2;  // bad input at start-up: nothing was started
    }
    auto& mcap = *opened;
    mcap.add_metadata("retreat", {{"scenario", s.name},
                                  {"seed", std::to_string(s.seed)},
                                  {"vendor", vendor},
                                  {"domain", std::to_string(s.dds.domain)},
                                  {"prefix", s.dds.prefix},
                                  {"retreat_version", RETREAT_PROJECT_VERSION},
                                  {"config", scenario::dump_json(s)}});
    auto transport = transport::make_transport(
        vendor, scenario::participant_options(s, program, wire::recorder_user_data, "recorder"));
    recorder::RecorderOptions options;
    options.prefix = s.dds.prefix;
    options.robots = s.arena.robots_inside + s.arena.robots_waiting;
    options.plans = s.run.plans;
    options.external_robots = s.arena.external_robots;
    options.answers_kept = s.run.recorders > 0;
    options.scene = s.arena;
    recorder::Recorder recorder(*transport, mcap, options);
    std::fprintf(stderr, "retreat-record: recording domain %d (%s) into %s\n", s.dds.domain,
                 vendor.c_str(), command_line.out.c_str());

    while (!scenario::stop_requested()) {
      transport->wait(std::chrono::milliseconds(100));
      recorder.poll(now_ns());
    }
    recorder.poll(now_ns());  // what arrived before the stop

    const auto dropped = recorder.overflowed();
    mcap.add_metadata("retreat.recorder",
                      {{"messages", std::to_string(mcap.message_count())},
                       {"dropped", std::to_string(dropped)},
                       {"robots_covered", std::to_string(recorder.robots_covered())},
                       {"scene_updates", std::to_string(recorder.scene_updates())}});
    mcap.close();
    std::fprintf(stderr, "retreat-record: %llu messages on %zu topics into %s; dropped %llu%s\n",
                 static_cast<unsigned long long>(recorder.messages()), recorder.counts().size(),
                 command_line.out.c_str(), static_cast<unsigned long long>(dropped),
                 dropped > 0 ? " (the recorder fell behind)" : "");
    scenario::limit_teardown(program, scenario::teardown_limit, dropped > 0 ? 4 : 0);
    return dropped > 0 ? 4 : 0;
  } catch (const std::invalid_argument& e) {
    scenario::report_error(program, e.what());
    return 2;
  } catch (const std::exception& e) {
    scenario::report_error(program, e.what());
    return 1;
  }
}
