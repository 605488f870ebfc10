// retreat-arena with real retreat-agent processes over each vendor: runs complete, write their
// run directory, give the same trajectory whatever carries the messages, survive a killed agent,
// wait for a slow one, drop and count bad decisions, and refuse bad input with one line and exit
// code 2. DDS domains: the arena_program block, and the robot_link_fastdds and mixed_swarm
// blocks borrowed under the CTest resource lock dds_domains_90_97 (tests/integration/CMakeLists.txt).

#include <gtest/gtest.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <thread>
#include <nlohmann/json.hpp>

#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
using testing::ChildProcess;

// Read when a test runs: main() points TMPDIR at the process's scratch directory.
std::string tmp_dir() { return ::testing::TempDir(); }

/// A small, fast swarm: 4 robots at λ = 1.33 robots/m² in the kinetic world, L = 10 s, K_p =
/// 0.1 so that robots do retreat within a minute (λ̂ is noisy and often above λ* = 1.51).
std::string small_scenario(double duration = 60) {
  // One file per test: ctest runs the tests of this file in parallel processes.
  const std::string path = tmp_dir() + "/arena_small_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                           std::to_string(static_cast<int>(duration)) + ".yaml";
  std::ofstream(path) << "name: arena-small\nseed: 11\n"
                      << "agent: {L: 10, dt: 0.03, K_p: 0.1, lambda_in: 0.02}\n"
                      << "arena: {encounter_model: kinetic, robots_inside: 3, robots_waiting: 1}\n"
                      << "run: {duration: " << duration << ", agent_timeout: 1.5, startup_timeout: 20}\n";
  return path;
}

struct Swarm {
  std::vector<ChildProcess> agents;
  std::optional<ChildProcess> arena;
};

Swarm start(const std::string& scenario, const std::string& arena_vendor,
            const std::vector<std::string>& agent_vendors, int domain, const std::string& out,
            const std::vector<std::string>& extra = {}) {
  Swarm s;
  for (std::size_t i = 0; i < agent_vendors.size(); ++i) {
    std::vector<std::string> argv = {RETREAT_AGENT_BIN, "--robot-id", std::to_string(i), "--scenario", scenario,
                                     "--dds", agent_vendors[i], "--domain", std::to_string(domain)};
    argv.insert(argv.end(), extra.begin(), extra.end());
    s.agents.emplace_back(argv, out + "_agent" + std::to_string(i) + ".log");
  }
  std::vector<std::string> argv = {RETREAT_ARENA_BIN, "--scenario", scenario, "--dds", arena_vendor,
                                   "--domain", std::to_string(domain), "--out", out};
  argv.insert(argv.end(), extra.begin(), extra.end());
  s.arena.emplace(argv, out + "_arena.log");
  return s;
}

json finish(Swarm& s, const std::string& out) {
  const auto code = s.arena->wait_for(retreat::testing::hang_ceiling);
  EXPECT_TRUE(code.has_value()) << "the arena did not finish";
  EXPECT_EQ(code.value_or(-1), 0) << testing::read_file(out + "_arena.log");
  for (auto& a : s.agents) a.stop();
  std::ifstream in(out + "/summary.json");
  EXPECT_TRUE(in.good()) << "no summary.json in " << out;
  return in.good() ? json::parse(in) : json{};
}

bool built(const std::string& vendor) {
  const auto v = transport::dds_vendors();
  return std::find(v.begin(), v.end(), vendor) != v.end();
}

TEST(ArenaProgram, ARunOverEitherVendorOrMixedGivesTheSameTrajectory) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const auto scenario = small_scenario();
  const std::vector<std::string> all_fast(4, "fastdds"), all_cyclone(4, "cyclonedds");
  const std::vector<std::string> mixed = {"fastdds", "cyclonedds", "fastdds", "cyclonedds"};
  auto a = start(scenario, "fastdds", all_fast, testing::domains::robot_link_fastdds.at(0), tmp_dir() + "/run_fast");
  auto ja = finish(a, tmp_dir() + "/run_fast");
  auto b = start(scenario, "cyclonedds", all_cyclone, testing::domains::robot_link_fastdds.at(1), tmp_dir() + "/run_cyclone");
  auto jb = finish(b, tmp_dir() + "/run_cyclone");
  auto c = start(scenario, "cyclonedds", mixed, testing::domains::robot_link_fastdds.at(2), tmp_dir() + "/run_mixed");
  auto jc = finish(c, tmp_dir() + "/run_mixed");
  ASSERT_FALSE(ja.empty() || jb.empty() || jc.empty());
  EXPECT_EQ(ja["ticks"], 2000);
  EXPECT_EQ(ja["agents"]["started"], 4);
  EXPECT_EQ(ja["agents"]["lost"], 0);
  EXPECT_EQ(ja["trajectory_sha256"].get<std::string>().size(), 64u);
  EXPECT_EQ(ja["trajectory_sha256"], jb["trajectory_sha256"]);
  EXPECT_EQ(ja["trajectory_sha256"], jc["trajectory_sha256"]);
  for (const char* f : {"scenario.yaml", "telemetry.csv", "agents.csv", "summary.json"}) {
    EXPECT_TRUE(std::filesystem::exists(tmp_dir() + "/run_fast/" + f)) << f;
  }
  // telemetry.csv: a header and one row per tick.
  std::ifstream telemetry(tmp_dir() + "/run_fast/telemetry.csv");
  const auto rows = std::count(std::istreambuf_iterator<char>(telemetry), {}, '\n');
  EXPECT_EQ(rows, 1 + 2000);
}

TEST(ArenaProgram, ADifferentSeedGivesADifferentTrajectory) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto scenario = small_scenario();
  const std::vector<std::string> agents(4, vendor);
  auto a = start(scenario, vendor, agents, testing::domains::robot_link_fastdds.at(3), tmp_dir() + "/run_seed11");
  auto ja = finish(a, tmp_dir() + "/run_seed11");
  auto b = start(scenario, vendor, agents, testing::domains::robot_link_fastdds.at(4), tmp_dir() + "/run_seed12", {"--set", "seed=12"});
  auto jb = finish(b, tmp_dir() + "/run_seed12");
  ASSERT_FALSE(ja.empty() || jb.empty());
  // Both runs had decisions to tell apart (otherwise the hashes could only differ by chance).
  EXPECT_GT(ja["agents"]["retreated"].get<int>() + jb["agents"]["retreated"].get<int>(), 0);
  EXPECT_NE(ja["trajectory_sha256"], jb["trajectory_sha256"]);
}

TEST(ArenaProgram, AKilledAgentIsDeclaredLostAndTheRunCompletes) {
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  // 1,000 simulated seconds (33,334 ticks) take several wall seconds: time enough to kill an
  // agent in the middle.
  const auto scenario = small_scenario(1000);
  // K_p = λ_in = 0: ε ≡ 0, no robot ever retreats, so the killed agent's robot is still inside.
  auto s = start(scenario, vendor, std::vector<std::string>(4, vendor), testing::domains::mixed_swarm.at(0), tmp_dir() + "/run_kill",
                 {"--set", "agent.K_p=0", "--set", "agent.lambda_in=0"});
  std::this_thread::sleep_for(1500ms);
  ASSERT_TRUE(s.arena->running());
  s.agents[1].signal(SIGKILL);
  const auto j = finish(s, tmp_dir() + "/run_kill");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["agents"]["started"], 4);
  EXPECT_EQ(j["agents"]["lost"], 1);
  EXPECT_EQ(j["ticks"], 33334);
}

// A loaded machine makes an agent slow, not dead (run.agent_hang_timeout): robot 0's agent
// stopped (SIGSTOP) for 4 s, four times run.agent_timeout but well within its participant's
// lease (Cyclone DDS 10 s, Fast DDS 20 s), stays matched, is waited for, and answers when
// continued: nobody is lost and the run completes. Declared lost at run.agent_timeout before.
TEST(ArenaProgram, AnAgentThatIsSlowButStillThereIsWaitedForNotLost) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto scenario = small_scenario(1000);
  // K_p = λ_in = 0: nobody retreats, so robot 0's agent is still answering when it is stopped.
  auto s = start(scenario, vendor, std::vector<std::string>(4, vendor), testing::domains::mixed_swarm.at(1),
                 tmp_dir() + "/run_slow", {"--set", "agent.K_p=0", "--set", "agent.lambda_in=0", "--set", "run.agent_timeout=1"});
  std::this_thread::sleep_for(1500ms);
  ASSERT_TRUE(s.arena->running());
  s.agents[0].signal(SIGSTOP);
  std::this_thread::sleep_for(4s);
  s.agents[0].signal(SIGCONT);
  const auto j = finish(s, tmp_dir() + "/run_slow");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["agents"]["started"], 4);
  EXPECT_EQ(j["agents"]["lost"], 0);
  EXPECT_GE(j["slow_answers"].get<std::uint64_t>(), 1u);
  EXPECT_EQ(j["ticks"], 33334);
  EXPECT_NE(testing::read_file(tmp_dir() + "/run_slow_arena.log").find("is still matched: waiting up to run.agent_hang_timeout"),
            std::string::npos);
}

TEST(ArenaProgram, ARealTimeRunPacesTicksByTheClockAndCompletes) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  // 30 simulated seconds at 20x: 1,000 ticks in about 1.5 wall seconds.
  const auto scenario = small_scenario(30);
  auto s = start(scenario, vendor, std::vector<std::string>(4, vendor), testing::domains::mixed_swarm.at(2), tmp_dir() + "/run_realtime",
                 {"--set", "run.mode=realtime", "--set", "run.speed=20"});
  const auto j = finish(s, tmp_dir() + "/run_realtime");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["mode"], "realtime");
  EXPECT_EQ(j["ticks"], 1000);
  EXPECT_EQ(j["agents"]["started"], 4);
  // Paced by the clock: 30 s at 20x cannot take less than 1.5 s of wall time.
  EXPECT_GE(j["wall_seconds"].get<double>(), 1.5);
}

TEST(ArenaProgram, DecisionsForUnknownRobotsOrPastTicksAreDroppedAndCounted) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto scenario = small_scenario(1000);
  const int domain = testing::domains::arena_program.at(0);
  auto s = start(scenario, vendor, std::vector<std::string>(4, vendor), domain, tmp_dir() + "/run_rogue");
  // A rogue participant writes on robot 0's decision topic: a robot id that is not the topic's,
  // and a decision for a tick long past.
  auto rogue = transport::make_transport(vendor, {domain, "rogue", "", ""});
  auto writer = rogue->create_writer<wire::Decision>({wire::decision_topic("retreat", 0), transport::QosIntent::control()});
  ASSERT_TRUE(testing::eventually([&] { return writer.matched_count() > 0; }, retreat::testing::hang_ceiling));
  std::this_thread::sleep_for(500ms);
  for (int i = 0; i < 5; ++i) {
    writer.write({99, 1, 0.03, true});  // robot 99 on robot 0's topic
    writer.write({0, 0, 0.0, true});    // tick 0, long past
  }
  writer.wait_for_acknowledgments(retreat::testing::hang_ceiling);
  const auto j = finish(s, tmp_dir() + "/run_rogue");
  ASSERT_FALSE(j.empty());
  EXPECT_GE(j["decisions_dropped"].get<int>(), 10);
  EXPECT_EQ(j["agents"]["lost"], 0);
}

TEST(ArenaProgramBadInput, EachBadValueGivesOneLineNamingItAndExitCodeTwo) {
  const auto scenario = small_scenario();
  struct Case {
    std::vector<std::string> set;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {{"arena.shape=hexagon"}, "arena.shape"},
      {{"arena.semi_axis_x=0"}, "arena.semi_axis_x = 0"},
      {{"arena.width=-1", "arena.shape=rectangle"}, "arena.width = -1"},
      {{"arena.robots_inside=5000", "arena.encounter_model=physical"}, "arena.robots_inside"},
      {{"model.delta=0.01"}, "model.delta"},
      {{"arena.encounter_model=quantum"}, "arena.encounter_model"},
      {{"arena.queue=infinite"}, "arena.queue"},
      {{"run.mode=turbo"}, "run.mode = 'turbo'"},
  };
  // An --out that holds a recorded run is not written over (--resume continues one).
  const std::string recorded = tmp_dir() + "/arena_recorded";
  std::filesystem::create_directories(recorded);
  std::ofstream(recorded + "/telemetry.csv") << "an earlier run\n";
  const auto [code, text] = testing::run_to_exit(
      {RETREAT_ARENA_BIN, "--scenario", scenario, "--dds", "inmemory", "--out", recorded}, tmp_dir() + "/arena_recorded.log");
  EXPECT_EQ(code, 2) << text;
  EXPECT_EQ(text, "retreat-arena: --out '" + recorded + "': holds a recorded run (" + recorded +
                      "/telemetry.csv); give a new directory (--resume continues a run an arena left)\n");
  EXPECT_EQ(testing::read_file(recorded + "/telemetry.csv"), "an earlier run\n");
  EXPECT_FALSE(std::filesystem::exists(recorded + "/scenario.yaml")) << "the arena wrote into it";
  for (const auto& c : cases) {
    std::vector<std::string> argv = {RETREAT_ARENA_BIN, "--scenario", scenario, "--dds", "inmemory"};
    for (const auto& s : c.set) {
      argv.push_back("--set");
      argv.push_back(s);
    }
    const std::string log = tmp_dir() + "/arena_bad.log";
    const auto [code, text] = testing::run_to_exit(argv, log);
    EXPECT_EQ(code, 2) << c.expected;
    EXPECT_NE(text.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << "not one line: " << text;
  }
}

}  // namespace
}  // namespace retreat
