#include "launch.hpp"

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "retreat/launch/child_process.hpp"

namespace retreat::experiment {

std::atomic<int> stop_signal{0};

void run_launch(const std::string& launcher, const LaunchRequest& r) {
  std::vector<std::string> argv = {launcher, r.scenario, "--seeds", r.seeds.text(), "--out", r.out,
                                   "--no-bridge"};
  if (r.in_process) {
    argv.emplace_back("--in-process");
    if (r.jobs) argv.insert(argv.end(), {"--jobs", std::to_string(*r.jobs)});
  } else {
    if (!r.dds.empty()) argv.insert(argv.end(), {"--dds", r.dds});
    if (r.domain) argv.insert(argv.end(), {"--domain", std::to_string(*r.domain)});
  }
  for (const auto& o : r.overrides) argv.insert(argv.end(), {"--set", o});
  std::string command;
  for (const auto& a : argv) command += (command.empty() ? "" : " ") + a;
  std::fprintf(stderr, "retreat-experiment: %s\n", command.c_str());

  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(r.log).parent_path(), ec);
  launch::ChildProcess child("retreat-launch", argv, r.log);
  using namespace std::chrono_literals;
  while (child.running()) {
    if (const int signo = stop_signal.load(); signo != 0) {
      // The launcher stops its agents and arena on SIGTERM and updates the summary.
      child.signal(SIGTERM);
      launch::stop_all({&child}, 30s);
      throw Stopped{signo};
    }
    std::this_thread::sleep_for(50ms);
  }
  const auto& status = *child.poll();
  if (status.code == 2) {
    throw UsageError("retreat-launch refused the run (" + r.log + " says why)");
  }
  if (status.code != 0) {
    throw RunFailure("retreat-launch " + status.describe() + "; its output is in " + r.log);
  }
}

}  // namespace retreat::experiment
