// The launcher's capacity check: what each vendor's settings and each shipped profile let one
// host's domain hold, and the one-line refusals for participants, tasks and memory. Host limits
// are passed in, so these hold on any machine.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "retreat/launch/capacity.hpp"

namespace retreat::launch {
namespace {

const std::string profiles = std::string(RETREAT_PROFILES) + "/";

/// A host with room for anything.
constexpr HostLimits roomy{std::uint64_t{1} << 40, 1u << 30, 100};

std::string write_profile(const std::string& name, const std::string& text) {
  const auto path = ::testing::TempDir() + "/capacity_" + name + ".xml";
  std::ofstream(path) << text;
  return path;
}

Plan plan_for(const std::string& vendor, bool bridge) {
  Plan p;
  p.vendors.label = vendor;
  p.vendors.arena = vendor == "mixed" ? "fastdds" : vendor;
  p.bridge_exe = bridge ? "/usr/bin/retreat-bridge" : "";
  return p;
}

TEST(DiscoveryLimit, TheBuiltInSettingsOfEitherVendorHold120ParticipantsPerDomain) {
  for (const char* vendor : {"fastdds", "cyclonedds"}) {
    const auto limit = discovery_limit(vendor, "");
    EXPECT_EQ(limit.participants, 120u) << vendor;
    EXPECT_NE(limit.settings.find("built-in"), std::string::npos) << limit.settings;
  }
}

TEST(DiscoveryLimit, ReadsEveryShippedProfileAsItsCommentsSay) {
  EXPECT_EQ(discovery_limit("cyclonedds", profiles + "cyclonedds-loopback.xml").participants, 120u);
  EXPECT_EQ(discovery_limit("cyclonedds", profiles + "cyclonedds-star-agent.xml").participants, std::nullopt);
  EXPECT_EQ(discovery_limit("cyclonedds", profiles + "cyclonedds-star-agent.xml").agents, cyclone_star_agents);
  EXPECT_EQ(discovery_limit("cyclonedds", profiles + "cyclonedds-loopback.xml").agents, std::nullopt);
  EXPECT_EQ(discovery_limit("fastdds", profiles + "fastdds-loopback.xml").participants, 120u);
  EXPECT_EQ(discovery_limit("fastdds", profiles + "fastdds-discovery-server-client.xml").participants, std::nullopt);
  EXPECT_EQ(discovery_limit("fastdds", profiles + "fastdds-multihost.xml").participants, 16u);
  // The hub's index comes from the environment, 0 by default: one participant per host.
  ::unsetenv("RETREAT_DDS_PARTICIPANT_INDEX");
  EXPECT_EQ(discovery_limit("cyclonedds", profiles + "cyclonedds-star-hub.xml").participants, 1u);
}

TEST(DiscoveryLimit, ExpandsTheEnvironmentAsCycloneDoes) {
  // cyclonedds-multihost.xml: ParticipantIndex ${RETREAT_DDS_PARTICIPANT_INDEX:-none},
  // MaxAutoParticipantIndex ${RETREAT_DDS_MAX_PARTICIPANT_INDEX:-9}.
  const auto multihost = profiles + "cyclonedds-multihost.xml";
  ::unsetenv("RETREAT_DDS_PARTICIPANT_INDEX");
  ::unsetenv("RETREAT_DDS_MAX_PARTICIPANT_INDEX");
  EXPECT_EQ(discovery_limit("cyclonedds", multihost).participants, std::nullopt);
  ::setenv("RETREAT_DDS_PARTICIPANT_INDEX", "auto", 1);
  EXPECT_EQ(discovery_limit("cyclonedds", multihost).participants, 10u);
  ::setenv("RETREAT_DDS_MAX_PARTICIPANT_INDEX", "49", 1);
  EXPECT_EQ(discovery_limit("cyclonedds", multihost).participants, 50u);
  ::unsetenv("RETREAT_DDS_PARTICIPANT_INDEX");
  ::unsetenv("RETREAT_DDS_MAX_PARTICIPANT_INDEX");
}

TEST(DiscoveryLimit, CommentsDoNotCountAndMalformedFilesAreRefusedByName) {
  const auto commented = write_profile(
      "commented", "<CycloneDDS><!-- <ParticipantIndex>auto</ParticipantIndex> --><Domain/></CycloneDDS>");
  EXPECT_EQ(discovery_limit("cyclonedds", commented).participants, std::nullopt);
  const auto broken = write_profile("broken", "<CycloneDDS><Domain></CycloneDDS>");
  try {
    discovery_limit("cyclonedds", broken);
    FAIL() << "a malformed profile was read";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(broken), std::string::npos) << e.what();
  }
}

TEST(CapacityRefusal, CountsTheArenaTheLauncherAndTheBridgeBesideTheAgents) {
  scenario::Scenario s;  // built-in settings: 120 per domain
  EXPECT_FALSE(capacity_refusal(plan_for("cyclonedds", false), s, 118, roomy));  // 120
  const auto refused = capacity_refusal(plan_for("cyclonedds", false), s, 119, roomy);
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("121 DDS participants"), std::string::npos) << *refused;
  EXPECT_NE(refused->find("at most 120"), std::string::npos) << *refused;
  EXPECT_NE(refused->find("star"), std::string::npos) << "names the way out: " << *refused;
  EXPECT_TRUE(capacity_refusal(plan_for("fastdds", true), s, 118, roomy)) << "the bridge is one more";
  EXPECT_TRUE(capacity_refusal(plan_for("mixed", true), s, 200, roomy));
  // --record: the recorder is one more participant, and is named.
  auto recorded = plan_for("cyclonedds", true);
  recorded.record_exe = "/usr/bin/retreat-record";
  EXPECT_FALSE(capacity_refusal(recorded, s, 116, roomy));  // 120
  const auto with_recorder = capacity_refusal(recorded, s, 117, roomy);
  ASSERT_TRUE(with_recorder);
  EXPECT_NE(with_recorder->find("121 DDS participants (117 agents, the arena, the launcher, the bridge and the recorder)"),
            std::string::npos)
      << *with_recorder;
}

TEST(CapacityRefusal, ACycloneStarIsRefusedBeyondTheAgentsItWasMeasuredToRun) {
  // No index to run out of, but endpoint discovery grows as 2N^2: measured to work with 300
  // agents and to fail with 400 (docs/benchmarks.md, "Discovery").
  scenario::Scenario s;
  s.dds.profile = profiles + "cyclonedds-star-agent.xml";
  EXPECT_FALSE(capacity_refusal(plan_for("cyclonedds", true), s, 300, roomy));
  const auto refused = capacity_refusal(plan_for("cyclonedds", true), s, 301, roomy);
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("301 agents"), std::string::npos) << *refused;
  EXPECT_NE(refused->find("at most 300"), std::string::npos) << *refused;
  EXPECT_NE(refused->find("cyclonedds-star-agent.xml"), std::string::npos) << *refused;
  EXPECT_TRUE(capacity_refusal(plan_for("mixed", true), s, 1000, roomy)) << "mixed: Cyclone agents too";
  // The Fast DDS discovery server was not measured to break: not refused.
  s.dds.profile = profiles + "fastdds-discovery-server-client.xml";
  EXPECT_FALSE(capacity_refusal(plan_for("fastdds", true), s, 1000, roomy));
}

TEST(CapacityRefusal, ASwarmOnSeveralDomainsIsCountedPerDomainAndTheRefusalSaysHowManyDomainsFit) {
  // Discovery is per domain: dds.domains K puts every K-th agent on each domain.
  scenario::Scenario s;
  s.dds.profile = profiles + "cyclonedds-star-agent.xml";
  const auto refused = capacity_refusal(plan_for("cyclonedds", true), s, 1000, roomy);
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("--set dds.domains=4"), std::string::npos) << "ceil(1000 / 300): " << *refused;
  s.dds.domains = 4;  // 250 per domain
  EXPECT_FALSE(capacity_refusal(plan_for("cyclonedds", true), s, 1000, roomy));
  s.dds.domains = 3;  // 334 per domain
  const auto three = capacity_refusal(plan_for("cyclonedds", true), s, 1000, roomy);
  ASSERT_TRUE(three);
  EXPECT_NE(three->find("334 agents in each of 3 domains"), std::string::npos) << *three;
  // Built-in settings: 120 participants per domain, 3 of them not agents.
  scenario::Scenario builtin;
  builtin.dds.domains = 2;
  EXPECT_FALSE(capacity_refusal(plan_for("cyclonedds", true), builtin, 234, roomy));  // 117 + 3 per domain
  const auto full = capacity_refusal(plan_for("cyclonedds", true), builtin, 235, roomy);
  ASSERT_TRUE(full);
  EXPECT_NE(full->find("121 DDS participants (118 agents, the arena, the launcher and the bridge) in each of 2 domains"),
            std::string::npos)
      << *full;
  EXPECT_NE(full->find("--set dds.domains=3"), std::string::npos) << "ceil(235 / 117): " << *full;
}

TEST(CapacityRefusal, TooFewTasksOrTooLittleMemoryIsRefusedWithTheLimit) {
  scenario::Scenario s;
  s.dds.profile = profiles + "cyclonedds-star-agent.xml";
  // 100 Cyclone agents: about 1,000 threads; 500 tasks left of 1,400.
  const auto tasks = capacity_refusal(plan_for("cyclonedds", false), s, 100, {std::uint64_t{1} << 40, 1400, 900});
  ASSERT_TRUE(tasks);
  EXPECT_NE(tasks->find("1400"), std::string::npos) << *tasks;
  EXPECT_NE(tasks->find("ulimit -u"), std::string::npos) << *tasks;
  EXPECT_FALSE(capacity_refusal(plan_for("cyclonedds", false), s, 40, {std::uint64_t{1} << 40, 1400, 900}));
  // 100 agents: about 600 MiB; 100 MiB available.
  const auto memory = capacity_refusal(plan_for("cyclonedds", false), s, 100, {100u << 20, 1u << 30, 100});
  ASSERT_TRUE(memory);
  EXPECT_NE(memory->find("100 MiB"), std::string::npos) << *memory;
}

/// An in-process plan of @p robots at the start (@p waiting of them queued), @p seeds seeds and
/// @p jobs at once (given on the command line when @p given, else the default).
Plan in_process_plan(std::uint32_t robots, std::uint32_t waiting, std::size_t seeds, unsigned jobs, bool given) {
  Plan p;
  p.options.in_process = true;
  if (given) p.options.jobs = jobs;
  p.jobs = jobs;
  p.scenario.arena.robots_inside = robots - waiting;
  p.scenario.arena.robots_waiting = waiting;
  for (std::size_t i = 0; i < seeds; ++i) p.seeds.push_back(i + 1);
  return p;
}

TEST(InProcessFit, RobotsAtTheStartTimesTheRunsAtOnceMustFitTheAvailableMemory) {
  // 10^6 robots: 10^6 · 16 KiB = 15625 MiB a run. 20000 MiB available: one run fits, two do not.
  const HostLimits host{std::uint64_t{20000} << 20, 1u << 30, 100};
  EXPECT_EQ(in_process_robot_memory_estimate, 16u << 10);

  const auto lowered = in_process_fit(in_process_plan(1000000, 2, 100, 2, false), host);
  EXPECT_EQ(lowered.jobs, 1u) << "the default (the core count) is lowered to what fits";
  EXPECT_FALSE(lowered.refusal);
  ASSERT_TRUE(lowered.notice);
  EXPECT_EQ(*lowered.notice,
            "1 seed at a time, not 2 (by default one per core): 1000000 robots (arena.robots_inside + arena.robots_waiting) "
            "with their agents need about 15625 MiB of memory a run, and 20000 MiB is available (MemAvailable)");

  const auto given = in_process_fit(in_process_plan(1000000, 0, 100, 2, true), host);
  ASSERT_TRUE(given.refusal) << "a --jobs that was asked for is not lowered behind the user's back";
  EXPECT_EQ(given.refusal->rfind("--jobs 2: 1000000 robots", 0), 0u) << *given.refusal;
  EXPECT_NE(given.refusal->find("2 at once about 31250 MiB"), std::string::npos) << *given.refusal;
  EXPECT_NE(given.refusal->find("at most --jobs 1 fits"), std::string::npos) << *given.refusal;

  // One seed runs alone whatever --jobs says: nothing to lower or refuse.
  const auto one_seed = in_process_fit(in_process_plan(1000000, 0, 1, 4, true), host);
  EXPECT_EQ(one_seed.jobs, 1u);
  EXPECT_FALSE(one_seed.refusal);
  EXPECT_FALSE(one_seed.notice);

  const auto none = in_process_fit(in_process_plan(1000000, 0, 3, 1, true), {std::uint64_t{15000} << 20, 1u << 30, 100});
  ASSERT_TRUE(none.refusal) << "not even one run fits";
  EXPECT_EQ(*none.refusal,
            "1000000 robots (arena.robots_inside + arena.robots_waiting) with their agents need about 15625 MiB of "
            "memory a run in process, and 15000 MiB is available (MemAvailable): run fewer robots, or the swarm as "
            "processes spread over several hosts");

  // A Robotarium-sized swarm fits any host: every seed the plan asks for runs at once.
  const auto small = in_process_fit(in_process_plan(12, 2, 100, 2, false), host);
  EXPECT_EQ(small.jobs, 2u);
  EXPECT_FALSE(small.refusal);
  EXPECT_FALSE(small.notice);
}

// RTPS well-known ports: 7400 + 250·domain .. + 249. With Linux's default ephemeral ports
// (32768..60999) the first block that reaches them is domain 101's (32650..32899).
TEST(EphemeralPorts, DomainsWhosePortsReachTheEphemeralRangeAreNamedWithTheWayOut) {
  EXPECT_EQ(well_known_ports(0).first, 7400u);
  EXPECT_EQ(well_known_ports(101).last, 32899u);
  EXPECT_FALSE(ephemeral_port_warning(0, 1, linux_default_ephemeral_ports));
  EXPECT_FALSE(ephemeral_port_warning(81, 20, linux_default_ephemeral_ports)) << "81..100 end at port 32649";
  const auto one = ephemeral_port_warning(101, 1, linux_default_ephemeral_ports);
  ASSERT_TRUE(one);
  EXPECT_NE(one->find("DDS domain 101 uses the well-known ports 32650..32899, inside this host's ephemeral ports "
                      "32768..60999"),
            std::string::npos)
      << *one;
  EXPECT_NE(one->find("prefer domain ids below 101"), std::string::npos) << *one;
  const auto many = ephemeral_port_warning(150, 20, linux_default_ephemeral_ports);
  ASSERT_TRUE(many);
  EXPECT_NE(many->find("DDS domains 150..169 use the well-known ports 44900..49899"), std::string::npos) << *many;
  // A host whose ephemeral ports begin higher (sysctl net.ipv4.ip_local_port_range) allows more.
  EXPECT_FALSE(ephemeral_port_warning(150, 20, PortRange{50000, 60999}));
  const auto high = ephemeral_port_warning(180, 1, PortRange{50000, 60999});
  ASSERT_TRUE(high);
  EXPECT_NE(high->find("prefer domain ids below 170"), std::string::npos) << *high;
}

TEST(EphemeralPorts, AreReadFromThisKernel) {
  const auto r = read_ephemeral_ports();
  EXPECT_LE(r.first, r.last);
  EXPECT_GT(r.first, 0u);
}

TEST(HostLimits, AreReadFromThisKernel) {
  const auto h = read_host_limits();
  EXPECT_GT(h.memory_available, 0u);
  EXPECT_GT(h.tasks_allowed, h.tasks_in_use) << "this test itself runs";
  EXPECT_GT(h.tasks_in_use, 0u);
}

}  // namespace
}  // namespace retreat::launch
