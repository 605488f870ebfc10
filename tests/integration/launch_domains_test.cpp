// retreat-launch with a swarm over several DDS domains (dds.domains): robot r's agent is on
// domain D + r mod K and nowhere else, the arena on every one; over each vendor's star profiles
// (the Cyclone star pair, and the Fast DDS discovery-server pair, whose server moves to port + i
// on the i-th domain) the run has the in-process trajectory with every agent matched and none
// lost. The 1,000-agent runs this is for are a benchmark (deploy/bench/lockstep_scale.sh
// --domains, docs/benchmarks.md).
//
// Domains: this file borrows 90..96 (the robot-link and mixed-swarm blocks) and holds the CTest
// resource lock dds_domains_90_97 of those suites (tests/integration/launch.cmake).

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "launch_support.hpp"
#include "retreat/testing/domains.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat::launch_test {
namespace {

using namespace std::chrono_literals;

// Each test on domains of its own: a stopped swarm's processes may hold their ports a little while.
constexpr int domain_observed = testing::domains::robot_link_fastdds.at(0);        // 90..92
constexpr int domain_cyclone_star = testing::domains::robot_link_fastdds.at(3);    // 93..94
constexpr int domain_fastdds_server = testing::domains::mixed_swarm.at(0);         // 95..96

std::vector<std::string> args(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

/// The user data of every participant an observer on @p domain alone sees, itself left out.
std::set<std::string> seen_on(const transport::Transport& observer) {
  std::set<std::string> out;
  for (const auto& p : observer.participants()) {
    if (p.guid != observer.guid()) out.insert(p.user_data);
  }
  return out;
}

// A Cyclone swarm of 12 agents over 3 domains (built-in settings, so that an observer may join):
// an observer on the second domain sees the arena and the agents of robots 1, 4, 7 and 10, and
// no other agent.
TEST(LaunchDomains, EachAgentIsOnItsRobotsDomainAndTheArenaOnEvery) {
  if (!built("cyclonedds")) GTEST_SKIP() << "needs Cyclone DDS";
  const auto dir = fresh_dir("domains-observed");
  // Does not end by itself (K_p = λ_in = 0: nobody leaves; 10^6 simulated s): stopped once seen.
  auto l = start_launch(dir, {robotarium, "--dds", "cyclonedds", "--domain", std::to_string(domain_observed), "--set",
                              "dds.domains=3", "--set", "agent.K_p=0", "--set",
                              "agent.lambda_in=0", "--set", "run.duration=1000000"});
  // However the test ends, the swarm is stopped as a user would (SIGTERM to the launcher).
  struct StopAtEnd {
    Launch& l;
    ~StopAtEnd() {
      if (l.process.running()) {
        l.process.signal(SIGTERM);
        l.process.wait_for(testing::hang_ceiling);
      }
    }
  } stop_at_end{l};
  auto observer = transport::make_transport("cyclonedds", {domain_observed + 1, "domains-observer", "retreat:observer", ""});
  const std::set<std::string> expected = {"retreat:arena", "retreat:agent:robot=1", "retreat:agent:robot=4",
                                          "retreat:agent:robot=7", "retreat:agent:robot=10"};
  const auto has_expected = [&] {
    const auto seen = seen_on(*observer);
    return std::includes(seen.begin(), seen.end(), expected.begin(), expected.end());
  };
  ASSERT_TRUE(testing::eventually(has_expected, testing::hang_ceiling))
      << "the observer did not see the domain's agents; " << log_of(dir);
  // Wait until the arena has matched every agent, so that every agent has announced itself
  // wherever it is; then the domain holds only these.
  const auto arena_log = [&] { return testing::read_file(l.out + "/logs/arena.log"); };
  ASSERT_TRUE(testing::eventually([&] { return arena_log().find("12 agents matched") != std::string::npos; },
                                  testing::hang_ceiling))
      << log_of(dir);
  std::this_thread::sleep_for(1s);
  std::set<std::string> seen = seen_on(*observer);
  seen.erase("retreat:launch");  // the launcher's telemetry reader (first domain only: absent here anyway)
  EXPECT_EQ(seen, expected);
  l.process.signal(SIGTERM);
  const auto code = l.process.wait_for(testing::hang_ceiling);
  ASSERT_TRUE(code.has_value());
  const auto j = read_json(l.out + "/summary.json");
  ASSERT_FALSE(j.empty()) << log_of(dir);
  EXPECT_EQ(j["agents"]["matched"], 12);
  EXPECT_EQ(j["agents"]["lost"], 0);
}

struct StarCase {
  const char* vendor;
  const char* hub;
  const char* agent;
  int domain;
};
void PrintTo(const StarCase& c, std::ostream* os) { *os << c.vendor; }

class LaunchDomainsStar : public ::testing::TestWithParam<StarCase> {};

TEST_P(LaunchDomainsStar, GivesTheInProcessTrajectoryWithEveryAgentMatched) {
  const auto c = GetParam();
  if (!built(c.vendor)) GTEST_SKIP() << "needs " << c.vendor;
  const std::string profiles = std::string(RETREAT_PROFILES) + "/";
  std::string hub = profiles + c.hub;
  std::string agent = profiles + c.agent;
  const auto dir = fresh_dir(std::string("domains-star-") + c.vendor);
  if (std::string(c.vendor) == "fastdds") {
    // The shipped pair with the server's port 11811 moved to 7320 (so as not to meet another
    // swarm's server): domain D + i's server is then at 7320 + i (i = 0, 1).
    for (auto* file : {&hub, &agent}) {
      std::ifstream in(*file);
      std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const auto at = text.find("<port>11811</port>");
      ASSERT_NE(at, std::string::npos) << *file;
      text.replace(at, 18, "<port>7320</port>");
      *file = dir + "/" + std::filesystem::path(*file).filename().string();
      std::ofstream(*file) << text;
    }
  }
  const std::vector<std::string> scenario = {robotarium, "--set", "run.plans=true"};
  const auto in_process = fresh_dir(std::string("domains-star-in-process-") + c.vendor);
  ASSERT_EQ(run_launch(in_process, args(scenario, {"--in-process"})), 0) << log_of(in_process);
  ASSERT_EQ(run_launch(dir, args(scenario, {"--dds", c.vendor, "--domain", std::to_string(c.domain), "--set",
                                            "dds.domains=2", "--arena-profile", hub,
                                            "--set", "dds.profile=" + agent})),
            0)
      << log_of(dir);
  const auto j = read_json(dir + "/run/summary.json");
  ASSERT_FALSE(j.empty()) << log_of(dir);
  EXPECT_EQ(j["agents"]["matched"], 12);
  EXPECT_EQ(j["agents"]["lost"], 0);
  EXPECT_GT(j["agents"]["retreated"].get<int>(), 0) << "the run exercises decisions";
  EXPECT_EQ(j["trajectory_sha256"], read_json(in_process + "/run/summary.json")["trajectory_sha256"]);
}

INSTANTIATE_TEST_SUITE_P(
    Vendors, LaunchDomainsStar,
    ::testing::Values(StarCase{"cyclonedds", "cyclonedds-star-hub.xml", "cyclonedds-star-agent.xml", domain_cyclone_star},
                      StarCase{"fastdds", "fastdds-discovery-server-hub.xml", "fastdds-discovery-server-client.xml",
                               domain_fastdds_server}),
    [](const auto& test) { return std::string(test.param.vendor); });

}  // namespace
}  // namespace retreat::launch_test
