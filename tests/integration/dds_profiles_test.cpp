// The DDS profiles shipped in deploy/dds/ work with the adapters, with real participants in
// separate processes: every profile is loaded through retreat::transport::make_transport with
// ParticipantOptions::profile set to the shipped file (by retreat_dds_swarm_node, which plays
// the arena-like hub and the agents), the hub matches every agent's reader and writer, and
// frames and decisions cross in both directions (a match alone proves nothing: only received
// samples prove delivery). The loopback profiles of the two vendors also work together in one
// swarm, and in the stars no agent discovers another agent.
//
// Each test has its own DDS domain id, from its block in retreat/testing/domains.hpp. Processes
// are stopped by PID. DDS stays on loopback: the last test checks that every shipped single-host profile pins it there.

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <set>

#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using retreat::testing::ChildProcess;
using retreat::testing::read_file;

const std::string profiles = std::string(RETREAT_SOURCE_DIR) + "/deploy/dds/";

/// The i-th domain id of this suite's block.
constexpr int domain(int i) { return retreat::testing::domains::dds_profiles.at(i); }

bool built(const std::string& vendor) {
  const auto vendors = retreat::transport::dds_vendors();
  return std::find(vendors.begin(), vendors.end(), vendor) != vendors.end();
}

#define REQUIRE_VENDOR(vendor) \
  if (!built(vendor)) GTEST_SKIP() << vendor << " is not built (RETREAT_WITH_... off)"

/// A fresh (emptied) directory for this test: logs go to the plain one, profiles the test
/// writes to the one with the suffix "_profiles".
std::string test_dir(const std::string& suffix = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir =
      fs::path(::testing::TempDir()) /
      ("dds_profiles_" + std::string(info->test_suite_name()) + "_" + info->name() + suffix);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

/// Writes `text` to `dir/name` and returns the path.
std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const auto path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

struct SwarmRun {
  std::string hub_result;               ///< the hub's result line (empty: none written)
  std::optional<int> hub_exit;          ///< 0: everything matched and answered
  std::vector<int> agent_participants;  ///< per agent: participants it discovered (-1: unknown)
  std::vector<std::string> agent_logs;
  std::string hub_log;
};

/// Starts a hub (arena-like) and `agents` agent processes on `domain`, waits for the hub's
/// verdict, stops everything by PID and collects what each process saw. Hub and agents may use
/// different vendors.
SwarmRun run_swarm(const std::string& hub_vendor, const std::string& hub_profile,
                   const std::string& agent_vendor, const std::string& agent_profile, int domain,
                   int agents, const std::vector<std::string>& env = {}) {
  const auto dir = test_dir();
  const auto result_path = dir + "/hub.result";
  ChildProcess hub({RETREAT_SWARM_NODE,
                    "--role",
                    "hub",
                    "--dds",
                    hub_vendor,
                    "--profile",
                    hub_profile,
                    "--domain",
                    std::to_string(domain),
                    "--agents",
                    std::to_string(agents),
                    "--match-timeout",
                    "30",
                    "--answer-timeout",
                    "15",
                    "--result",
                    result_path,
                    "--linger",
                    "--max-seconds",
                    "90"},
                   dir + "/hub.log", env);
  std::vector<ChildProcess> children;
  for (int i = 0; i < agents; ++i) {
    children.emplace_back(
        std::vector<std::string>{RETREAT_SWARM_NODE, "--role", "agent", "--dds", agent_vendor,
                                 "--profile", agent_profile, "--domain", std::to_string(domain),
                                 "--robot", std::to_string(i), "--max-seconds", "90"},
        dir + "/agent_" + std::to_string(i) + ".log", env);
  }
  retreat::testing::eventually([&] { return fs::exists(result_path) || !hub.running(); }, retreat::testing::hang_ceiling);
  SwarmRun run;
  run.hub_result = read_file(result_path);
  // Agents print what they discovered when they are stopped. Signal all, then reap each.
  for (auto& child : children) child.signal(SIGTERM);
  for (auto& child : children) child.stop();
  run.hub_exit = hub.stop();
  run.hub_log = read_file(dir + "/hub.log");
  const std::regex participants(R"(participants=(\d+))");
  for (int i = 0; i < agents; ++i) {
    const auto log = read_file(dir + "/agent_" + std::to_string(i) + ".log");
    std::smatch m;
    run.agent_participants.push_back(std::regex_search(log, m, participants) ? std::stoi(m[1])
                                                                             : -1);
    run.agent_logs.push_back(log);
  }
  return run;
}

SwarmRun run_swarm(const std::string& vendor, const std::string& hub_profile,
                   const std::string& agent_profile, int domain, int agents,
                   const std::vector<std::string>& env = {}) {
  return run_swarm(vendor, hub_profile, vendor, agent_profile, domain, agents, env);
}

void expect_everyone_matched_and_answered(const SwarmRun& run, int agents) {
  const auto n = std::to_string(agents);
  EXPECT_NE(run.hub_result.find("matched=" + n + "/" + n), std::string::npos)
      << "hub: " << run.hub_result << run.hub_log;
  EXPECT_NE(run.hub_result.find("answered=" + n + "/" + n), std::string::npos)
      << "hub: " << run.hub_result << run.hub_log;
  EXPECT_EQ(run.hub_exit, 0) << run.hub_log;
}

/// In a star no agent discovers another agent: each sees itself and the hub, nothing else.
void expect_star(const SwarmRun& run) {
  for (std::size_t i = 0; i < run.agent_participants.size(); ++i) {
    EXPECT_EQ(run.agent_participants[i], 2)
        << "agent " << i << " discovered " << run.agent_participants[i] << " participants; log:\n"
        << run.agent_logs[i];
  }
}

// ---- one host, simple discovery --------------------------------------------------------------

TEST(FastDdsLoopbackProfile, AHubAndThreeAgentsMatchAndExchangeSamples) {
  REQUIRE_VENDOR("fastdds");
  const auto p = profiles + "fastdds-loopback.xml";
  const auto run = run_swarm("fastdds", p, p, domain(0), 3);
  expect_everyone_matched_and_answered(run, 3);
}

TEST(CycloneLoopbackProfile, AHubAndThreeAgentsMatchAndExchangeSamples) {
  REQUIRE_VENDOR("cyclonedds");
  const auto p = profiles + "cyclonedds-loopback.xml";
  const auto run = run_swarm("cyclonedds", p, p, domain(1), 3);
  expect_everyone_matched_and_answered(run, 3);
}

TEST(LoopbackProfiles, AFastDdsHubAndCycloneAgentsFindEachOther) {
  REQUIRE_VENDOR("fastdds");
  REQUIRE_VENDOR("cyclonedds");
  // A mixed swarm: each process uses its own vendor's loopback profile.
  const auto run = run_swarm("fastdds", profiles + "fastdds-loopback.xml", "cyclonedds",
                             profiles + "cyclonedds-loopback.xml", domain(6), 3);
  expect_everyone_matched_and_answered(run, 3);
}

TEST(LoopbackProfiles, ACycloneHubAndFastDdsAgentsFindEachOther) {
  REQUIRE_VENDOR("fastdds");
  REQUIRE_VENDOR("cyclonedds");
  const auto run = run_swarm("cyclonedds", profiles + "cyclonedds-loopback.xml", "fastdds",
                             profiles + "fastdds-loopback.xml", domain(7), 3);
  expect_everyone_matched_and_answered(run, 3);
}

// ---- one host, star ----------------------------------------------------------------------------

TEST(FastDdsDiscoveryServerStar, ThirtyClientsMatchTheHubAndNeverDiscoverEachOther) {
  REQUIRE_VENDOR("fastdds");
  // The shipped files with the server's port 11811 moved to 7312 (below every RTPS port), so that
  // this test can neither collide with nor join a swarm running on this host: with a discovery
  // server the port, not the domain id, separates swarms. Nothing else is changed.
  const auto dir = test_dir("_profiles");
  const auto hub_text = read_file(profiles + "fastdds-discovery-server-hub.xml");
  const auto client_text = read_file(profiles + "fastdds-discovery-server-client.xml");
  ASSERT_NE(hub_text.find("<port>11811</port>"), std::string::npos);
  ASSERT_NE(client_text.find("<port>11811</port>"), std::string::npos);
  const auto hub =
      write_file(dir, "hub.xml", replace_all(hub_text, "<port>11811</port>", "<port>7312</port>"));
  const auto client = write_file(
      dir, "client.xml", replace_all(client_text, "<port>11811</port>", "<port>7312</port>"));
  const auto run = run_swarm("fastdds", hub, client, domain(2), 30);
  expect_everyone_matched_and_answered(run, 30);
  expect_star(run);
}

TEST(CycloneStar, ThirtyAgentsMatchTheHubAndNeverDiscoverEachOther) {
  REQUIRE_VENDOR("cyclonedds");
  // The hub's port follows from the domain id (7410 + 250 * domain): the files are used as shipped.
  const auto run = run_swarm("cyclonedds", profiles + "cyclonedds-star-hub.xml",
                             profiles + "cyclonedds-star-agent.xml", domain(3), 30);
  expect_everyone_matched_and_answered(run, 30);
  expect_star(run);
}

// ---- several hosts (exercised on loopback)
// -------------------------------------------------------

TEST(FastDdsMultihostProfile, FilledInWithLoopbackAddressesMatchesAndExchangesSamples) {
  REQUIRE_VENDOR("fastdds");
  auto text = read_file(profiles + "fastdds-multihost.xml");
  for (const char* placeholder : {"@HOST_ADDRESS@", "@PEER_ADDRESS_1@", "@PEER_ADDRESS_2@"}) {
    ASSERT_NE(text.find(placeholder), std::string::npos) << placeholder;
    text = replace_all(text, placeholder, "127.0.0.1");
  }
  const auto elements = std::regex_replace(text, std::regex(R"(<!--[\s\S]*?-->)"), "");
  ASSERT_EQ(elements.find('@'), std::string::npos)
      << "a placeholder the documentation does not name";
  const auto filled = write_file(test_dir("_profiles"), "fastdds-multihost-filled.xml", text);
  const auto run = run_swarm("fastdds", filled, filled, domain(4), 2);
  expect_everyone_matched_and_answered(run, 2);
}

TEST(CycloneMultihostProfile, FilledInFromTheEnvironmentMatchesAndExchangesSamples) {
  REQUIRE_VENDOR("cyclonedds");
  // As documented in the file for a network without multicast: unicast discovery with
  // participant indices, the peer being this host.
  const auto p = profiles + "cyclonedds-multihost.xml";
  const auto run = run_swarm("cyclonedds", p, p, domain(5), 2,
                             {"RETREAT_DDS_INTERFACE=lo", "RETREAT_DDS_MULTICAST=false",
                              "RETREAT_DDS_PARTICIPANT_INDEX=auto", "RETREAT_DDS_PEERS=127.0.0.1"});
  expect_everyone_matched_and_answered(run, 2);
}

TEST(CycloneMultihostProfile, WithoutAnInterfaceIsRefusedRatherThanGuessingOne) {
  REQUIRE_VENDOR("cyclonedds");
  ::unsetenv("RETREAT_DDS_INTERFACE");
  retreat::transport::ParticipantOptions options;
  options.domain_id = domain(7);  // only a profile load that fails: no participant
  options.profile = profiles + "cyclonedds-multihost.xml";
  EXPECT_THROW(retreat::transport::make_transport("cyclonedds", options), std::invalid_argument);
}

// ---- the adapter's handling of profile files ---------------------------------------------------

TEST(FastDdsProfileFiles, ASecondProfileFileInOneProcessIsRefusedNotSilentlyIgnored) {
  REQUIRE_VENDOR("fastdds");
  // Fast DDS keeps the first "retreat_participant" it loaded and only logs the clash; the
  // adapter turns that into an error instead of running with the wrong settings.
  retreat::transport::ParticipantOptions options;
  options.domain_id = retreat::testing::domains::dds_profile_files.at(0);
  options.profile = profiles + "fastdds-loopback.xml";
  auto first = retreat::transport::make_transport("fastdds", options);
  auto again = retreat::transport::make_transport("fastdds", options);  // same file: fine
  options.profile = profiles + "fastdds-discovery-server-client.xml";
  try {
    retreat::transport::make_transport("fastdds", options);
    FAIL() << "a second profile file was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("one profile file per process"), std::string::npos)
        << e.what();
  }
}

// ---- the loopback rule -------------------------------------------------------------------------

std::vector<std::string> all_matches(const std::string& text, const std::string& pattern) {
  std::vector<std::string> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
       ++it) {
    out.push_back((*it)[1]);
  }
  return out;
}

TEST(DdsProfiles, EverySingleHostProfilePinsDdsToLoopbackAndMultihostOnesGuessNothing) {
  std::set<std::string> files;
  for (const auto& e : fs::directory_iterator(profiles)) {
    if (e.path().extension() == ".xml") files.insert(e.path().filename().string());
  }
  const std::set<std::string> shipped = {"fastdds-loopback.xml",
                                         "fastdds-discovery-server-hub.xml",
                                         "fastdds-discovery-server-client.xml",
                                         "fastdds-multihost.xml",
                                         "cyclonedds-loopback.xml",
                                         "cyclonedds-star-hub.xml",
                                         "cyclonedds-star-agent.xml",
                                         "cyclonedds-multihost.xml"};
  // A new profile must be added here, with its checks, and to the tests above.
  EXPECT_EQ(files, shipped);

  for (const auto& name : files) {
    SCOPED_TRACE(name);
    const auto text = read_file(profiles + name);
    // XML comments may say anything; only elements count.
    const auto xml = std::regex_replace(text, std::regex(R"(<!--[\s\S]*?-->)"), "");
    const bool multihost = name.find("multihost") != std::string::npos;
    auto addresses = all_matches(xml, R"(<address>([^<]*)</address>)");
    for (const auto& a : all_matches(xml, R"#(address="([^"]*)")#")) addresses.push_back(a);
    if (name.rfind("fastdds", 0) == 0) {
      EXPECT_NE(xml.find(R"(profile_name="retreat_participant")"), std::string::npos);
      EXPECT_NE(xml.find("<useBuiltinTransports>false</useBuiltinTransports>"), std::string::npos)
          << "built-in transports (shared memory, UDP on every interface) must be off";
      EXPECT_NE(xml.find("<interfaceWhiteList>"), std::string::npos);
      EXPECT_EQ(xml.find("<metatrafficMulticastLocatorList>"), std::string::npos);
      EXPECT_EQ(xml.find("<defaultMulticastLocatorList>"), std::string::npos);
      // No multicast locator is created only when the unicast discovery locators are given.
      EXPECT_NE(xml.find("<metatrafficUnicastLocatorList>"), std::string::npos);
      EXPECT_FALSE(addresses.empty());
      for (const auto& a : addresses) {
        if (multihost) {
          EXPECT_TRUE(std::regex_match(a, std::regex("@[A-Z0-9_]+@")))
              << a << ": must be a placeholder";
        } else {
          EXPECT_EQ(a, "127.0.0.1");
        }
      }
    } else {
      const auto interfaces = all_matches(xml, R"#(<NetworkInterface\s+name="([^"]*)")#");
      ASSERT_EQ(interfaces.size(), 1u);
      EXPECT_EQ(xml.find("<NetworkInterfaceAddress"), std::string::npos);
      if (multihost) {
        // No default: an unset variable stops the process instead of picking some interface.
        EXPECT_TRUE(
            std::regex_match(interfaces[0], std::regex(R"(\$\{RETREAT_DDS_INTERFACE:\?[^}]+\})")))
            << interfaces[0];
      } else {
        EXPECT_EQ(interfaces[0], "lo");
        for (const auto& a : addresses) EXPECT_EQ(a, "127.0.0.1");
      }
    }
  }
}

}  // namespace
