// Round trip of one ProximityFrame -> Decision between two processes over retreat's own
// transport (retreat::transport, the adapters the arena and the agents use), per DDS vendor.
//
// The benchmark process is the arena side: it writes frame i on `retreat/robot_0/proximity` and
// waits for the Decision answering tick i on `retreat/robot_0/decision`. The agent side is a
// child process (this same executable with `--echo VENDOR DOMAIN`) that answers every frame at
// once: no controller, so the time is the transport's alone. A child process, not a second
// participant in this one: a Fast DDS and a Cyclone DDS participant on the same domain in one
// process abort, and a real swarm has them in separate processes anyway.
//
// Both sides use the built-in loopback-only settings (empty profile); QoS is the control intent
// (reliable, volatile, keep all). Domain ids 6 (Fast DDS) and 7 (Cyclone DDS): below 102, outside the ephemeral port range.
// Reported: the mean (manual time) and the p50 / p90 / p99 of the round trips, in µs.

#include <benchmark/benchmark.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "retreat/transport/factory.hpp"

extern char** environ;

namespace {

using namespace std::chrono_literals;
using retreat::transport::QosIntent;
namespace wire = retreat::wire;
namespace transport = retreat::transport;

constexpr wire::RobotId robot = 0;
std::string self_path;

std::atomic<bool> stop_echo{false};
void on_term(int) { stop_echo = true; }

/// The child: answers every frame with the Decision for its tick, until SIGTERM.
int run_echo(const std::string& vendor, int domain) {
  struct sigaction sa {};
  sa.sa_handler = on_term;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  auto t = transport::make_transport(vendor, {domain, "retreat-pingpong-echo", "retreat:agent:robot=0", ""});
  auto frames = t->create_reader<wire::ProximityFrame>(
      {wire::proximity_topic(wire::default_prefix, robot), QosIntent::control()});
  auto decisions = t->create_writer<wire::Decision>(
      {wire::decision_topic(wire::default_prefix, robot), QosIntent::control()});
  // Also ends when the benchmark process is gone (killed before it could stop this child).
  const pid_t parent = ::getppid();
  while (!stop_echo && ::getppid() == parent) {
    if (!t->wait(100ms)) continue;
    for (const auto& f : frames.take()) decisions.write({f.robot_id, f.tick, f.time, false});
  }
  return 0;
}

/// The echo child, started by path and stopped by PID.
class Echo {
 public:
  Echo(const std::string& vendor, int domain) {
    const std::string d = std::to_string(domain);
    std::vector<char*> argv = {const_cast<char*>(self_path.c_str()), const_cast<char*>("--echo"),
                               const_cast<char*>(vendor.c_str()), const_cast<char*>(d.c_str()), nullptr};
    if (posix_spawn(&pid_, self_path.c_str(), nullptr, nullptr, argv.data(), environ) != 0) pid_ = -1;
  }
  ~Echo() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    for (int i = 0; i < 300; ++i) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) return;
      std::this_thread::sleep_for(10ms);
    }
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  Echo(const Echo&) = delete;
  Echo& operator=(const Echo&) = delete;
  bool started() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  return v[i];
}

void BM_RoundTrip(benchmark::State& state, const std::string& vendor, int domain) {
  const auto vendors = transport::dds_vendors();
  if (std::find(vendors.begin(), vendors.end(), vendor) == vendors.end()) {
    state.SkipWithError((vendor + " is not built").c_str());
    return;
  }
  Echo echo(vendor, domain);
  if (!echo.started()) {
    state.SkipWithError("cannot start the echo process");
    return;
  }
  auto t = transport::make_transport(vendor, {domain, "retreat-pingpong", "retreat:arena", ""});
  auto frames = t->create_writer<wire::ProximityFrame>(
      {wire::proximity_topic(wire::default_prefix, robot), QosIntent::control()});
  auto decisions = t->create_reader<wire::Decision>(
      {wire::decision_topic(wire::default_prefix, robot), QosIntent::control()});
  std::int64_t tick = 0;
  const auto frame = [&](std::int64_t k) {
    return wire::ProximityFrame{robot, k, 0.03 * static_cast<double>(k), wire::Phase::inside, false, 0};
  };
  // Discovery, then pings until one comes back (both directions matched).
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  bool answered = false;
  while (!answered && std::chrono::steady_clock::now() < deadline) {
    if (frames.matched_count() == 0 || decisions.matched_count() == 0) {
      std::this_thread::sleep_for(20ms);
      continue;
    }
    frames.write(frame(tick++));
    const auto until = std::chrono::steady_clock::now() + 200ms;
    while (!answered && std::chrono::steady_clock::now() < until) {
      if (t->wait(50ms)) answered = !decisions.take().empty();
    }
  }
  if (!answered) {
    state.SkipWithError("the echo process never answered");
    return;
  }
  // Warm-up round trips, not measured.
  const auto round_trip = [&](std::int64_t k) {
    frames.write(frame(k));
    for (;;) {
      t->wait(1s);
      for (const auto& d : decisions.take()) {
        if (d.tick == k) return true;
      }
      if (frames.matched_count() == 0) return false;
    }
  };
  for (int i = 0; i < 200; ++i) round_trip(tick++);

  std::vector<double> us;
  us.reserve(static_cast<std::size_t>(state.max_iterations));
  for (auto _ : state) {
    const auto begin = std::chrono::steady_clock::now();
    if (!round_trip(tick++)) {
      state.SkipWithError("the echo process went away");
      break;
    }
    const auto seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    state.SetIterationTime(seconds);
    us.push_back(seconds * 1e6);
  }
  state.counters["p50_us"] = percentile(us, 0.50);
  state.counters["p90_us"] = percentile(us, 0.90);
  state.counters["p99_us"] = percentile(us, 0.99);
}

BENCHMARK_CAPTURE(BM_RoundTrip, fastdds, std::string("fastdds"), 6)
    ->Iterations(5000)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_RoundTrip, cyclonedds, std::string("cyclonedds"), 7)
    ->Iterations(5000)->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--echo") == 0) return run_echo(argv[2], std::atoi(argv[3]));
  char buf[4096];
  const auto n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  self_path = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string(argv[0]);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
