// A mixed real-and-simulated swarm over DDS: one real-time arena with simulated robots and
// emulated real robots (arena.external_robots): two retreat-robot-example processes in tracked
// mode (their own motion, clocks and loop jitter) and one robot driven by this test through the
// C++ RobotLink, which also pauses (frozen), sends bad poses (dropped and counted) and finally
// goes silent (lost). Every robot has an unmodified retreat-agent process. Also retreat-launch
// with a real robot. DDS domains: the mixed_swarm block of retreat/testing/domains.hpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "retreat/robot/robot_link.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using testing::ChildProcess;
using testing::eventually;
using testing::hang_ceiling;
namespace fs = std::filesystem;

struct Vendor {
  const char* name;
  int domain;
};

void PrintTo(const Vendor& v, std::ostream* os) { *os << v.name; }

constexpr std::uint32_t robots = 12;
constexpr std::uint32_t real_robots = 3;  // 0 and 1: example processes; 2: this test

class MixedSwarm : public ::testing::TestWithParam<Vendor> {
 protected:
  void SetUp() override {
    const auto vendors = transport::dds_vendors();
    if (std::find(vendors.begin(), vendors.end(), GetParam().name) == vendors.end()) {
      GTEST_SKIP() << GetParam().name << " is not built";
    }
    dir_ = ::testing::TempDir() + "/mixed_swarm_" + GetParam().name;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string dir_;
};

/// The rows of encounters.csv as (robot, other) pairs.
std::set<std::pair<std::uint32_t, std::uint32_t>> encounter_pairs(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  while (std::getline(in, line)) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    if (fields >> a >> b) pairs.insert({a, b});
  }
  return pairs;
}

TEST_P(MixedSwarm, RealAndSimulatedRobotsMeetTheRunCompletesAndBadPosesAreDroppedAndCounted) {
  const int domain = GetParam().domain;
  const auto scenario = dir_ + "/scenario.yaml";
  // A small rectangle with 12 robots (6.25 robots/m², four times λ*), so that robots meet often;
  // L = 15 s with K_p = 1000: every agent whose estimate is above λ* at t = 15 s retreats then. A
  // pose older than 0.5 s is frozen, older than 3 s lost. At most 25 s of real time.
  std::ofstream(scenario) << "name: mixed-swarm-test\nseed: 3\n"
                          << "arena: {shape: rectangle, width: 1.6, height: 1.2, robots_inside: " << robots
                          << ", robots_waiting: 0, external_robots: " << real_robots
                          << ", record_encounters: true, external_frozen_after: 0.5, external_lost_after: 3}\n"
                          << "agent: {L: 15, K_p: 1000, lambda_in: 0}\n"
                          << "run: {mode: realtime, duration: 25, startup_timeout: 60, agent_timeout: 30}\n"
                          << "dds: {vendor: " << GetParam().name << ", domain: " << domain << "}\n";
  const auto s = scenario::load(scenario);
  ASSERT_EQ(s.arena.external_robots, real_robots);

  ChildProcess arena({RETREAT_ARENA_BIN, "--scenario", scenario, "--out", dir_ + "/run"}, dir_ + "/arena.log");
  std::vector<ChildProcess> agents;
  for (std::uint32_t r = 0; r < robots; ++r) {
    agents.emplace_back(std::vector<std::string>{RETREAT_AGENT_BIN, "--robot-id", std::to_string(r), "--scenario", scenario},
                        dir_ + "/agent_" + std::to_string(r) + ".log");
  }
  std::vector<ChildProcess> examples;
  for (std::uint32_t r = 0; r < 2; ++r) {
    examples.emplace_back(
        std::vector<std::string>{RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", std::to_string(r), "--scenario", scenario,
                                 "--rate", r == 0 ? "10" : "30", "--jitter", "0.3", "--orbit", r == 0 ? "0.3" : "0.45",
                                 "--speed", "0.2", "--exit-radius", "1.2", "--pose-noise", "0.005",
                                 "--seed", std::to_string(7 + r), "--max-time", "40"},
        dir_ + "/robot_" + std::to_string(r) + ".log");
  }

  // Robot 2, driven here: 20 Hz ± 30 %, round the centre at 0.15 m/s on a 0.2 m circle.
  auto observer = transport::make_transport(GetParam().name, {domain, "observer", "test:observer", ""});
  auto statuses = observer->create_reader<wire::AgentStatus>({wire::agent_status_topic("retreat"), transport::QosIntent::state()});
  auto raw = observer->create_writer<wire::Poses>(
      {wire::tracked_pose_topic("retreat", 2), transport::QosIntent::control()});
  auto options = robot::link_options(s, 2);
  ASSERT_TRUE(options.tracked);
  robot::RobotLink link(options);
  ASSERT_TRUE(link.wait_for_agent(hang_ceiling)) << "robot 2's agent and the arena's pose reader";
  std::map<std::uint32_t, std::uint32_t> most_onsets;
  std::vector<transport::RemoteEndpoint> sources;
  double angle = 0.0;
  double last = link.now();
  auto drive = [&](double until, bool publish) {
    while (link.now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(35 + static_cast<int>(std::fmod(last * 7919.0, 30.0))));
      const double now = link.now();
      angle += 0.15 * (now - last) / 0.2;
      last = now;
      if (publish) {
        ASSERT_TRUE(link.report_pose(now, 0.2 * std::cos(angle), 0.2 * std::sin(angle), angle + M_PI / 2).has_value())
            << link.refused_reason();
      }
      link.poll();
      for (const auto& st : statuses.take()) most_onsets[st.robot_id] = std::max(most_onsets[st.robot_id], st.onsets_in_window);
    }
  };
  drive(2.0, true);
  // Bad poses on robot 2's topic: another robot's, NaN, a clock going back, and a jump across the
  // arena: none may move robot 2.
  wire::Poses bad;
  bad.arena_id = 7;
  bad.time = link.now();
  bad.robots.push_back({7, 0.0f, 0.0f, 0.0f, wire::Phase::inside, false});
  raw.write(bad);                                             // another robot's pose
  bad.arena_id = 2;
  bad.robots[0].robot_id = 2;
  bad.robots[0].x = std::nanf("");
  raw.write(bad);                                             // NaN
  bad.robots[0].x = 0.2f;
  bad.time = 0.0;
  raw.write(bad);                                             // the clock went back
  ASSERT_TRUE(link.report_pose(link.now(), 3.0, 0.0, 0.0).has_value());  // 3 m away at once
  drive(4.0, true);
  drive(5.0, false);  // 1 s without a pose: frozen
  drive(7.0, true);
  // Isolation: robot 2's link reads decisions from robot 2's agent only (checked below).
  sources = link.decision_sources();
  std::map<std::string, std::string> user_data;
  ASSERT_TRUE(eventually([&] {
    for (const auto& p : observer->participants()) user_data[p.guid] = p.user_data;
    return std::all_of(sources.begin(), sources.end(), [&](const auto& w) { return user_data.count(w.participant_guid) > 0; });
  }, hang_ceiling)) << "the observer never discovered the participants robot 2's link reads from";
  drive(12.0, false);  // silent from 7 s on: lost after 3 s, before the agents decide at 15 s

  // The run ends at 20 s; the example robots either drove out when told or keep going.
  const auto arena_code = arena.wait_for(hang_ceiling);
  ASSERT_TRUE(arena_code.has_value()) << "the arena did not end";
  EXPECT_EQ(*arena_code, 0) << testing::read_file(dir_ + "/arena.log");
  for (auto& e : examples) e.stop();
  for (auto& a : agents) a.stop();
  for (const auto& st : statuses.take()) most_onsets[st.robot_id] = std::max(most_onsets[st.robot_id], st.onsets_in_window);

  const auto summary = nlohmann::json::parse(std::ifstream(dir_ + "/run/summary.json"));
  const auto& external = summary.at("external");
  EXPECT_EQ(external.at("robots"), real_robots);
  EXPECT_GT(external.at("poses_accepted").get<std::uint64_t>(), 100u);
  EXPECT_EQ(external.at("poses_invalid"), 2) << "another robot's pose and a NaN";
  EXPECT_EQ(external.at("poses_clock_back"), 1);
  EXPECT_EQ(external.at("poses_jumped"), 1);
  EXPECT_GE(external.at("frozen").get<std::uint64_t>(), 2u) << "robot 2's pause and its silence";
  EXPECT_EQ(external.at("lost"), 1) << "robot 2 only";

  // Encounters between real and simulated robots (one record per contact; the tracker counts an
  // onset for each of the two robots).
  const auto pairs = encounter_pairs(dir_ + "/run/encounters.csv");
  std::set<std::uint32_t> simulated_partners;
  for (const auto& [a, b] : pairs) {
    if (a < real_robots && b >= real_robots && b < robots) simulated_partners.insert(b);
    if (b < real_robots && a >= real_robots && a < robots) simulated_partners.insert(a);
  }
  EXPECT_FALSE(simulated_partners.empty()) << pairs.size() << " encounter pairs, none between a real and a simulated robot";
  // ... and the real robots' agents counted onsets from the frames the arena made of them.
  for (std::uint32_t r = 0; r < 2; ++r) EXPECT_GT(most_onsets[r], 0u) << "robot " << r << "'s agent";

  // Robot 2 was lost: it departed in the arena's records.
  std::ifstream agents_csv(dir_ + "/run/agents.csv");
  std::string line;
  std::getline(agents_csv, line);
  std::map<std::uint32_t, std::vector<std::string>> rows;
  while (std::getline(agents_csv, line)) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    rows[static_cast<std::uint32_t>(std::stoul(cells.at(0)))] = cells;
  }
  ASSERT_EQ(rows.size(), robots);
  for (const auto b : simulated_partners) {
    EXPECT_NE(rows[b].at(8), "0") << "simulated robot " << b << " met a real robot: its onsets count it";
  }
  EXPECT_NE(rows[2].at(7), "-1") << "robot 2 departed when lost (departed_at)";
  // A real robot told to retreat left by its own motion: it departed.
  for (std::uint32_t r = 0; r < 2; ++r) {
    if (rows[r].at(4) == "1") {
      EXPECT_NE(rows[r].at(7), "-1") << "robot " << r << " retreated but never departed";
    }
  }

  ASSERT_FALSE(sources.empty());
  for (const auto& w : sources) {
    EXPECT_EQ(user_data[w.participant_guid], "retreat:agent:robot=2") << w.participant_guid;
  }
}

TEST(MixedSwarmLaunch, RetreatLaunchRunsASwarmWithARealRobotThatLeavesByItsOwnMotion) {
  const auto vendors = transport::dds_vendors();
  if (std::find(vendors.begin(), vendors.end(), "cyclonedds") == vendors.end()) GTEST_SKIP();
  const std::string dir = ::testing::TempDir() + "/mixed_swarm_launch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto scenario = dir + "/scenario.yaml";
  // 6 robots on 1.92 m² (twice λ*), robot 0 real; L = 5 s with K_p = 1000: an agent whose
  // estimate is above λ* at 5 s retreats then.
  std::ofstream(scenario) << "name: mixed-launch-test\nseed: 5\n"
                          << "arena: {shape: rectangle, width: 1.6, height: 1.2, robots_inside: 6, robots_waiting: 0, "
                             "external_robots: 1}\n"
                          << "agent: {L: 5, K_p: 1000, lambda_in: 0}\n"
                          << "run: {mode: realtime, duration: 12}\n"
                          << "dds: {vendor: cyclonedds, domain: " << testing::domains::mixed_swarm.at(2) << "}\n";
  ChildProcess robot({RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "0", "--scenario", scenario, "--rate", "20",
                      "--orbit", "0.3", "--speed", "0.2", "--exit-radius", "1.2", "--max-time", "40"},
                     dir + "/robot.log");
  const auto [code, output] = testing::run_to_exit(
      {RETREAT_LAUNCH_BIN, scenario, "--out", dir + "/run", "--domain", std::to_string(testing::domains::mixed_swarm.at(2)), "--no-bridge"}, dir + "/launch.log");
  ASSERT_EQ(code, 0) << output;
  robot.stop();
  const auto summary = nlohmann::json::parse(std::ifstream(dir + "/run/summary.json"));
  EXPECT_EQ(summary.at("agents").at("started"), 6) << "the real robot's agent too";
  EXPECT_GT(summary.at("external").at("poses_accepted").get<std::uint64_t>(), 0u);
  EXPECT_EQ(summary.at("external").at("lost"), 0);
  std::ifstream agents_csv(dir + "/run/agents.csv");
  std::string header;
  std::string row;
  std::getline(agents_csv, header);
  std::getline(agents_csv, row);  // robot 0
  std::vector<std::string> cells;
  std::stringstream cells_in(row);
  for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
  ASSERT_EQ(cells.at(0), "0");
  if (cells.at(4) == "1") {
    EXPECT_NE(cells.at(7), "-1") << "told to retreat, the real robot drove out and departed";
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Vendors, MixedSwarm,
                         ::testing::Values(Vendor{"cyclonedds", testing::domains::mixed_swarm.at(0)},
                                           Vendor{"fastdds", testing::domains::mixed_swarm.at(1)}),
                         [](const ::testing::TestParamInfo<Vendor>& v) { return std::string(v.param.name); });

}  // namespace
}  // namespace retreat
