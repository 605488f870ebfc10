// retreat-replay (bridge/replay holds its work; it lives here because it starts agents, as the
// launcher does): plays a recording's proximity frames to live agents and compares their answers
// with the recorded ones (docs/recording.md, "Replay").
//
//   retreat-replay run.mcap                      every robot, over the recording's vendor
//   retreat-replay run.mcap --dds cyclonedds     a Fast DDS recording, replayed over Cyclone DDS
//   retreat-replay run.mcap --robots 3 --pace recorded
//   retreat-replay run.mcap --controller adaptive-proportional --dds inmemory
//
// The agents are retreat-agent processes it starts (beside this program) on a scenario written
// from the recording's, or with --dds inmemory AgentNodes in this process; --no-agents leaves them
// to whoever runs them. Exit codes: 0 replayed, every answer as recorded (or, re-deciding,
// complete); 5 answers differ; 1 a robot's replay did not complete (an agent did not answer or
// died), or a failure; 2 bad input (one line).

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>
#include <vector>

#include "retreat/agent/agent_node.hpp"
#include "retreat/launch/child_process.hpp"
#include "retreat/replay/command_line.hpp"
#include "retreat/replay/replay.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/transport/inmemory.hpp"
#include "retreat/wire/topics.hpp"

namespace {

using namespace retreat;
using Clock = std::chrono::steady_clock;
constexpr const char* program = "retreat-replay";

nlohmann::json to_json(const wire::Decision& d) {
  return {{"robot", d.robot_id}, {"tick", d.tick}, {"time", d.time}, {"retreat", d.retreat}};
}

void write_report(const std::string& path, const replay::ReplayCommandLine& cl, const std::string& vendor,
                  const std::vector<replay::RobotOutcome>& outcomes) {
  nlohmann::json j;
  j["recording"] = cl.recording;
  j["dds"] = vendor;
  j["controller"] = cl.options.controller.empty() ? nlohmann::json(nullptr) : nlohmann::json(cl.options.controller);
  j["overrides"] = cl.options.agent_overrides;
  j["pace"] = cl.options.pace == replay::Pace::recorded ? "recorded" : "lockstep";
  for (const auto& o : outcomes) {
    nlohmann::json r = {{"robot", o.robot},
                        {"frames", o.frames},
                        {"answered", o.answered},
                        {"same", o.same},
                        {"different", o.different},
                        {"unchecked", o.unchecked},
                        {"resent", o.resent},
                        {"not_awaited", o.not_awaited},
                        {"recorded_retreat_tick", o.recorded_retreat_tick},
                        {"replayed_retreat_tick", o.replayed_retreat_tick},
                        {"complete", o.failure.empty()}};
    if (!o.failure.empty()) r["failure"] = o.failure;
    if (o.first_difference) {
      r["first_difference"] = {{"frame_tick", o.first_difference->frame_tick},
                               {"recorded", to_json(o.first_difference->recorded)},
                               {"replayed", to_json(o.first_difference->replayed)}};
    }
    j["robots"].push_back(r);
  }
  const std::string tmp = path + ".tmp";
  std::ofstream(tmp) << j.dump(2) << '\n';
  std::filesystem::rename(tmp, path);
}

/// The directory of this program (retreat-agent is beside it, in the build tree as installed).
std::filesystem::path own_directory() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path() : exe.parent_path();
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = scenario::parse_or_report(program, [&] { return replay::parse_replay_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& cl = std::get<replay::ReplayCommandLine>(parsed);
  scenario::install_stop_handlers();

  replay::Recording recording;
  std::vector<replay::RobotScript> scripts;
  scenario::Scenario s;
  std::string vendor;
  try {
    recording = replay::load_recording(cl.recording);
    scripts = replay::make_scripts(recording, cl.options);
    s = replay::agent_scenario(recording, cl.options);
    vendor = !cl.dds.empty() ? cl.dds : recording.metadata.count("vendor") ? recording.metadata.at("vendor") : "fastdds";
    scenario::apply_override(s, "dds.vendor=" + vendor);
    if (cl.domain >= 0) s.dds.domain = cl.domain;
    // On this machine, pinned to loopback: not the recorded swarm's profile or PKI.
    s.dds.profile.clear();
    s.dds.security = scenario::Security::off;
  } catch (const std::exception& e) {
    scenario::report_error(program, e.what());
    return 2;
  }
  if (recording.undecodable + recording.invalid > 0) {
    std::fprintf(stderr, "retreat-replay: %llu recorded samples did not decode and %llu were invalid: dropped\n",
                 static_cast<unsigned long long>(recording.undecodable),
                 static_cast<unsigned long long>(recording.invalid));
  }
  if (recording.recorder_dropped > 0) {
    std::fprintf(stderr, "retreat-replay: the recorder lost %lld samples: answers to missing frames are not checked\n",
                 static_cast<long long>(recording.recorder_dropped));
  }
  const bool redecide = cl.options.redecide();
  const bool plans = s.run.plans;
  std::vector<replay::RobotOutcome> outcomes;
  std::optional<std::filesystem::path> work;  // the agents' scenario and logs
  try {
    transport::ParticipantOptions options = scenario::participant_options(s, program, wire::replay_user_data, "replay");
    const bool in_memory = vendor == "inmemory";
    std::shared_ptr<transport::InMemoryBus> bus;
    std::unique_ptr<transport::Transport> driver_transport;
    if (in_memory) {
      // A private bus stepped by this thread alone (the driver and every agent): nothing locks.
      bus = transport::make_inmemory_bus(transport::Threading::confined);
      driver_transport = transport::make_inmemory_transport(bus, options);
    } else {
      driver_transport = transport::make_transport(vendor, options);
    }
    replay::Driver driver(*driver_transport, s.dds.prefix, scripts, plans, cl.options.pace,
                          std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(cl.answer_timeout)));

    struct InProcessAgent {
      std::unique_ptr<transport::Transport> transport;
      std::unique_ptr<agent::AgentNode> node;
    };
    std::vector<InProcessAgent> nodes;
    std::vector<launch::ChildProcess> children;
    if (in_memory) {
      for (const auto& script : scripts) {
        auto& a = nodes.emplace_back();
        auto o = options;
        o.name = "retreat-agent/robot_" + std::to_string(script.robot);
        a.transport = transport::make_inmemory_transport(bus, o);
        a.node = std::make_unique<agent::AgentNode>(s, script.robot, *a.transport);
      }
    } else if (cl.spawn_agents) {
      std::string pattern = (std::filesystem::temp_directory_path() / "retreat-replay-XXXXXX").string();
      if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a directory like " + pattern);
      work = pattern;
      const auto scenario_file = (*work / "scenario.yaml").string();
      std::ofstream(scenario_file) << scenario::dump(s);
      const auto agent_program = (own_directory() / "retreat-agent").string();
      children.reserve(scripts.size());
      for (const auto& script : scripts) {
        const auto id = std::to_string(script.robot);
        children.emplace_back("agent " + id,
                              std::vector<std::string>{agent_program, "--scenario", scenario_file, "--robot-id", id},
                              (*work / ("agent_" + id + ".log")).string());
      }
    }
    const auto pump = [&] {
      if (in_memory) {
        for (auto& a : nodes) a.node->spin_once(std::chrono::nanoseconds(0));
      } else {
        driver_transport->wait(std::chrono::milliseconds(1));
      }
    };
    const auto child_failed = [&]() -> std::string {
      for (auto& c : children) {
        if (const auto& st = c.poll(); st && st->code != 0) return c.name() + " " + st->describe() + " (" + c.log_path() + ")";
      }
      return {};
    };
    // Start-up: every robot's agent matched (as an arena waits for its agents).
    const auto startup_deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                     std::chrono::duration<double>(s.run.startup_timeout));
    while (!driver.matched()) {
      if (scenario::stop_requested()) return 1;
      if (const auto failed = child_failed(); !failed.empty()) throw std::runtime_error(failed);
      if (Clock::now() > startup_deadline) {
        throw std::runtime_error("the agents did not match within run.startup_timeout (" +
                                 std::to_string(s.run.startup_timeout) + " s)");
      }
      pump();
      std::this_thread::sleep_for(std::chrono::milliseconds(in_memory ? 0 : 20));
    }
    std::fprintf(stderr, "retreat-replay: replaying %zu robots from %s over %s (%s)\n", scripts.size(),
                 cl.recording.c_str(), vendor.c_str(), redecide ? "re-deciding every tick"
                                                                 : "checking the recorded answers");
    auto next_child_check = Clock::now();
    while (driver.step(Clock::now())) {
      if (scenario::stop_requested()) break;
      if (Clock::now() >= next_child_check) {
        if (const auto failed = child_failed(); !failed.empty()) throw std::runtime_error(failed);
        next_child_check = Clock::now() + std::chrono::milliseconds(500);
      }
      pump();
    }
    outcomes = driver.outcomes();
    std::vector<launch::ChildProcess*> running;
    for (auto& c : children) running.push_back(&c);
    launch::stop_all(running, std::chrono::seconds(5));
  } catch (const std::exception& e) {
    scenario::report_error(program, std::string(e.what()) + (work ? " (logs in " + work->string() + ")" : ""));
    return 1;
  }
  std::cout << replay::format_outcomes(outcomes, redecide) << std::flush;
  if (!cl.report.empty()) write_report(cl.report, cl, vendor, outcomes);
  bool complete = !scenario::stop_requested();
  bool same = true;
  for (const auto& o : outcomes) {
    complete = complete && o.failure.empty();
    same = same && o.different == 0;
  }
  if (complete && work) std::filesystem::remove_all(*work);
  if (!complete && work) std::fprintf(stderr, "retreat-replay: the agents' logs are in %s\n", work->c_str());
  scenario::limit_teardown(program, scenario::teardown_limit, !complete ? 1 : (same || redecide) ? 0 : 5);
  if (!complete) return 1;
  return same || redecide ? 0 : 5;
}
