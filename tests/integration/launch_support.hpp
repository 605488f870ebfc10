#pragma once
/// @file
/// Helpers of the retreat-launch tests: start the real launcher as a child process, read the
/// run directory's JSON files, check that processes are gone. Assertions are on exit codes and
/// files the launcher and the arena write, never on log text.
///
/// Domain ids: the launch tests use 50..64 only, one per TEST (the constants are in each file).

#include <signal.h>
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat::launch_test {

using namespace std::chrono_literals;
using nlohmann::json;

inline const std::string launcher = RETREAT_LAUNCH_BIN;
/// Where the launcher looks for the bridge (a link into the build tree, present once built).
inline const std::string bridge_program =
    std::filesystem::path(RETREAT_LAUNCH_BIN).parent_path().string() + "/retreat-bridge";
inline const std::string scenarios = RETREAT_SCENARIOS;
inline const std::string robotarium = scenarios + "/robotarium-2019.yaml";

/// robotarium-2019 shortened to 400 simulated seconds (13,334 lockstep ticks: ~10 s of wall time
/// over Fast DDS, less over Cyclone DDS) so that each run stays under ~15 s; everything else is
/// the shipped scenario.
inline const std::vector<std::string> short_robotarium = {"--set", "run.duration=400"};
inline constexpr std::int64_t short_robotarium_ticks = 13334;

/// A fresh directory for one test's files (removed first if a previous run left it).
inline std::string fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("retreat-launch-test-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// The launcher running as a child of the test; its output goes to `<dir>/launch.log`.
struct Launch {
  std::string out;  ///< the run directory (`<dir>/run`)
  testing::ChildProcess process;
};

/// Without `bridge`, --no-bridge: a bridge serves HTTP (bridge.http), which tests running in
/// parallel cannot share; the bridge test gives it a free port.
inline Launch start_launch(const std::string& dir, std::vector<std::string> args, bool bridge = false) {
  std::vector<std::string> argv = {launcher};
  argv.insert(argv.end(), args.begin(), args.end());
  if (!bridge) argv.push_back("--no-bridge");
  const std::string out = dir + "/run";
  argv.push_back("--out");
  argv.push_back(out);
  return Launch{out, testing::ChildProcess(argv, dir + "/launch.log")};
}

/// Runs the launcher to its end; returns its exit code (-1 if it did not end in `timeout`).
inline int run_launch(const std::string& dir, const std::vector<std::string>& args,
                      std::chrono::milliseconds timeout = testing::hang_ceiling, bool bridge = false) {
  auto l = start_launch(dir, args, bridge);
  const auto code = l.process.wait_for(timeout);
  if (!code) {
    l.process.stop();
    return -1;
  }
  return *code;
}

inline json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) return json{};
  try {
    return json::parse(in);
  } catch (const json::exception&) {
    return json{};
  }
}

/// The PIDs of every child in `<out>/processes.json` (arena, agents, bridge).
inline std::vector<pid_t> child_pids(const json& processes) {
  std::vector<pid_t> out;
  if (processes.contains("arena")) out.push_back(processes["arena"]["pid"].get<pid_t>());
  if (processes.contains("agents")) {
    for (const auto& a : processes["agents"]) out.push_back(a["pid"].get<pid_t>());
  }
  if (processes.contains("bridge") && !processes["bridge"].is_null()) {
    out.push_back(processes["bridge"]["pid"].get<pid_t>());
  }
  return out;
}

/// The process exists and is not a zombie.
inline bool process_alive(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  if (!stat) return false;
  std::string text((std::istreambuf_iterator<char>(stat)), {});
  const auto close = text.rfind(')');
  return close != std::string::npos && close + 2 < text.size() && text[close + 2] != 'Z';
}

/// PIDs among `pids` that still run.
inline std::vector<pid_t> alive(const std::vector<pid_t>& pids) {
  std::vector<pid_t> out;
  for (const auto p : pids) {
    if (process_alive(p)) out.push_back(p);
  }
  return out;
}

inline bool built(const std::string& vendor) {
  const auto v = transport::dds_vendors();
  return std::find(v.begin(), v.end(), vendor) != v.end();
}

inline std::string log_of(const std::string& dir) { return testing::read_file(dir + "/launch.log"); }

}  // namespace retreat::launch_test
