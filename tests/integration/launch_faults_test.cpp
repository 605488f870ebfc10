// retreat-launch under faults: agents killed mid-run (the run completes, they are counted lost,
// the launcher exits 0), the arena killed more often than the launcher resumes it (it stops
// everything and exits 1; one resume is in faults_test), the
// launcher itself stopped by SIGTERM (every child stopped, the summary still written). In every
// case no child is left behind: each PID of processes.json is gone.

#include <gtest/gtest.h>

#include <initializer_list>
#include <set>
#include <thread>
#include <vector>

#include "retreat/testing/domains.hpp"
#include "launch_support.hpp"

namespace retreat::launch_test {
namespace {

// Domain ids of this file: 54, 55, 57.
constexpr int domain_kill_agents = testing::domains::launch.at(4);
constexpr int domain_kill_arena = testing::domains::launch.at(5);
constexpr int domain_stop_launcher = testing::domains::launch.at(7);

/// Waits for `<out>/processes.json` (written once every child has started).
json wait_for_processes(const std::string& out) {
  json j;
  testing::eventually([&] {
    j = read_json(out + "/processes.json");
    return !j.empty();
  }, retreat::testing::hang_ceiling);
  return j;
}

/// Waits until the arena's telemetry (read on our own participant) reaches simulated time `t`.
bool wait_for_simulated_time(const std::string& vendor, int domain, double t) {
  auto participant = transport::make_transport(vendor, {domain, "launch-test-watch", "", ""});
  auto reader = participant->create_reader<wire::ArenaTelemetry>(
      {wire::arena_telemetry_topic("retreat"), transport::QosIntent::state()});
  return testing::eventually([&] {
    participant->wait(50ms);
    for (const auto& m : reader.take()) {
      if (m.time >= t) return true;
    }
    return false;
  }, retreat::testing::hang_ceiling);
}

pid_t pid_of_agent(const json& processes, int robot) {
  for (const auto& a : processes["agents"]) {
    if (a["robot"] == robot) return a["pid"].get<pid_t>();
  }
  return -1;
}

/// Launches robotarium with @p args on @p vendor and @p domain, kills the agents of @p robots
/// (SIGKILL) once the arena's telemetry reaches simulated time @p kill_after, waits for the
/// launcher, which must exit 0 with 12 agents started and no child left, and reads summary.json
/// into @p summary. Fatal failures end it (the caller checks HasFatalFailure()).
void kill_agents_and_finish(const std::string& name, const std::string& vendor, int domain,
                            const std::vector<std::string>& args, double kill_after,
                            std::initializer_list<int> robots, json& summary) {
  const auto dir = fresh_dir(name);
  std::vector<std::string> argv = {robotarium, "--dds", vendor, "--domain", std::to_string(domain)};
  argv.insert(argv.end(), args.begin(), args.end());
  auto l = start_launch(dir, argv);
  const auto processes = wait_for_processes(l.out);
  ASSERT_EQ(processes["agents"].size(), 12u) << log_of(dir);
  ASSERT_TRUE(wait_for_simulated_time(vendor, domain, kill_after)) << log_of(dir);
  for (int robot : robots) {
    const pid_t pid = pid_of_agent(processes, robot);
    ASSERT_GT(pid, 0);
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
  }
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  EXPECT_EQ(*code, 0) << log_of(dir);
  summary = read_json(l.out + "/summary.json");
  ASSERT_FALSE(summary.empty()) << log_of(dir);
  EXPECT_EQ(summary["agents"]["started"], 12);
  EXPECT_TRUE(alive(child_pids(processes)).empty());
}

TEST(LaunchFaults, TwoAgentsKilledMidRunAreCountedLostAndTheRunCompletes) {
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  // 200 simulated seconds (6,667 ticks); an agent silent for 1 wall second is lost. Robots 10 and
  // 11 wait in the queue until t = 50 s and 66 s: killed at t >= 10 s, still there, still answering.
  json j;
  kill_agents_and_finish("kill-agents", vendor, domain_kill_agents,
                         {"--set", "run.duration=200", "--set", "run.agent_timeout=1", "--set", "run.plans=false"},
                         10.0, {10, 11}, j);
  if (HasFatalFailure()) return;
  EXPECT_EQ(j["agents"]["lost"], 2);
  EXPECT_EQ(j["ticks"], 6667);
}

TEST(LaunchFaults, WithPlansTwoAgentsKilledWhileTheirPlansAreInForceAreCountedLostAndTheRunCompletes) {
  // run.plans with a 2-tick horizon: a frame every other tick or so, so the run leaves the test
  // seconds of wall time to kill in; K_p = λ_in = 0: nobody retreats, robots 0 and 1 stay inside
  // the whole 1,200 s, and their agents' deaths are found out at the next frame their plans leave
  // to the arena (no answer within run.agent_timeout: lost), whenever they die after t = 1 s.
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  json j;
  kill_agents_and_finish("kill-agents-plans", vendor, testing::domains::launch_plans.at(3),
                         {"--set", "run.agent_timeout=1", "--set", "run.plans=true", "--set", "run.plan_horizon=2",
                          "--set", "agent.K_p=0", "--set", "agent.lambda_in=0"},
                         1.0, {0, 1}, j);
  if (HasFatalFailure()) return;
  EXPECT_EQ(j["agents"]["lost"], 2);
  EXPECT_EQ(j["agents"]["retreated"], 0);
  EXPECT_EQ(j["ticks"], 40000);
  EXPECT_GT(j["decisions_planned"].get<std::uint64_t>(), 0u);
}

TEST(LaunchFaults, AnArenaKilledMoreOftenThanItIsResumedStopsEveryChildAndTheLauncherFails) {
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  const auto dir = fresh_dir("kill-arena");
  // Per tick: the 1,200 s run lasts long enough to be killed in (with the shipped scenario's
  // plans it may end within a second).
  auto l = start_launch(dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain_kill_arena), "--set",
                              "run.plans=false"});
  const auto processes = wait_for_processes(l.out);
  ASSERT_FALSE(processes.empty()) << log_of(dir);
  ASSERT_TRUE(wait_for_simulated_time(vendor, domain_kill_arena, 5.0)) << log_of(dir);
  // The first arena and the 5 the launcher resumes (its budget), each killed once listed.
  std::vector<pid_t> children = child_pids(processes);
  std::set<pid_t> arenas;
  for (int kill = 0; kill <= 5; ++kill) {
    json current;
    ASSERT_TRUE(testing::eventually(
        [&] {
          current = read_json(l.out + "/processes.json");
          return !current.empty() && arenas.count(current["arena"]["pid"].get<pid_t>()) == 0;
        },
        retreat::testing::hang_ceiling))
        << "the launcher did not resume the arena after kill " << kill << "; " << log_of(dir);
    const pid_t arena = current["arena"]["pid"].get<pid_t>();
    arenas.insert(arena);
    children.push_back(arena);
    ASSERT_EQ(::kill(arena, SIGKILL), 0);
  }
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  EXPECT_EQ(*code, 1) << log_of(dir);
  EXPECT_TRUE(alive(children).empty());
  EXPECT_FALSE(std::filesystem::exists(l.out + "/summary.json"));
}

TEST(LaunchFaults, SigtermStopsEveryChildAndKeepsTheSummary) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto dir = fresh_dir("stop-launcher");
  auto l = start_launch(dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain_stop_launcher), "--set",
                              "run.plans=false"});  // per tick: still running when stopped
  const auto processes = wait_for_processes(l.out);
  ASSERT_FALSE(processes.empty()) << log_of(dir);
  ASSERT_TRUE(wait_for_simulated_time(vendor, domain_stop_launcher, 5.0)) << log_of(dir);
  l.process.signal(SIGTERM);
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  EXPECT_EQ(*code, 128 + SIGTERM) << log_of(dir);
  EXPECT_TRUE(alive(child_pids(processes)).empty());
  // The arena wrote the summary of the part that ran, and the launcher completed it.
  const auto j = read_json(l.out + "/summary.json");
  ASSERT_FALSE(j.empty()) << log_of(dir);
  EXPECT_LT(j["ticks"].get<int>(), 40000);
  EXPECT_EQ(j["agents"]["started"], 12);
  EXPECT_EQ(j["launch"]["mode"], "processes");
}

}  // namespace
}  // namespace retreat::launch_test
