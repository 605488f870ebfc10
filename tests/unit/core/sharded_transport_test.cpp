// One swarm over several domains (dds.domains, idl/transport/include/retreat/transport/sharded.hpp),
// with make_transport over the in-memory transport, whose buses are per domain id like DDS
// domains: robot r's topics are on domain D + r mod K, shared topics are written on D and read
// on every domain. The same routing over real DDS processes: tests/integration/launch_domains_test.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "retreat/transport/factory.hpp"
#include "retreat/transport/sharded.hpp"

namespace retreat::transport {
namespace {

constexpr int first_domain = 200;  // in-memory buses: process-local, no ports
constexpr int domains = 3;
constexpr QosIntent control = QosIntent::control();

std::unique_ptr<Transport> on_domain(int domain, const std::string& user_data) {
  return make_transport("inmemory", {domain, user_data, user_data, ""});
}

std::unique_ptr<Transport> on_every_domain(const std::string& user_data) {
  ParticipantOptions options{first_domain, user_data, user_data, ""};
  options.domains = domains;
  return make_transport("inmemory", options);
}

wire::ProximityFrame frame(wire::RobotId robot) { return {robot, 1, 0.03, wire::Phase::inside, false, 0}; }

// The one bound on dds.domains (the scenario check and validate(ParticipantOptions) both use it):
// 64, fewer where the domain ids run out at 232.
TEST(ShardedTransport, TheDomainsASwarmMaySpanEndWithTheDomainIds) {
  EXPECT_EQ(wire::max_domains_from(0), wire::max_domains);
  EXPECT_EQ(wire::max_domains_from(169), 64);
  EXPECT_EQ(wire::max_domains_from(200), 33);
  EXPECT_EQ(wire::max_domains_from(wire::max_domain_id), 1);
  auto options = ParticipantOptions{200, "arena", "retreat:arena", ""};
  options.domains = 33;
  EXPECT_NO_THROW(validate(options));
  options.domains = 34;
  EXPECT_THROW(validate(options), std::invalid_argument);
}

TEST(ShardedTransport, ARobotsTopicsAreOnlyOnItsOwnDomain) {
  EXPECT_EQ(wire::robot_domain(first_domain, domains, 0), 200);
  EXPECT_EQ(wire::robot_domain(first_domain, domains, 4), 201);
  EXPECT_EQ(wire::robot_domain(first_domain, domains, 5), 202);
  auto arena = on_every_domain("retreat:arena");
  ASSERT_NE(dynamic_cast<ShardedTransport*>(arena.get()), nullptr);
  auto own = on_domain(201, "robot 4's agent");    // robot 4's domain
  auto other = on_domain(200, "robot 4 elsewhere");  // a domain robot 4 is not on
  auto own_reader = own->create_reader<wire::ProximityFrame>({wire::proximity_topic("retreat", 4), control});
  auto other_reader = other->create_reader<wire::ProximityFrame>({wire::proximity_topic("retreat", 4), control});
  auto writer = arena->create_writer<wire::ProximityFrame>({wire::proximity_topic("retreat", 4), control});
  EXPECT_EQ(writer.matched_count(), 1u);
  ASSERT_EQ(writer.write(frame(4)), WriteResult::ok);
  EXPECT_EQ(own_reader.take().size(), 1u);
  EXPECT_TRUE(other_reader.take().empty());

  // The other way: robot 4's decisions reach the arena from its own domain only.
  auto decisions = arena->create_reader<wire::Decision>({wire::decision_topic("retreat", 4), control});
  auto own_writer = own->create_writer<wire::Decision>({wire::decision_topic("retreat", 4), control});
  auto other_writer = other->create_writer<wire::Decision>({wire::decision_topic("retreat", 4), control});
  EXPECT_EQ(other_writer.matched_count(), 0u);
  ASSERT_EQ(own_writer.write({4, 1, 0.03, true}), WriteResult::ok);
  ASSERT_EQ(other_writer.write({4, 2, 0.06, true}), WriteResult::ok);
  EXPECT_TRUE(arena->wait(std::chrono::seconds(0))) << "a sample on any domain wakes the sharded transport";
  const auto taken = decisions.take();
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken.front().tick, 1);
}

TEST(ShardedTransport, SharedTopicsAreWrittenOnTheFirstDomainAndReadOnEvery) {
  auto arena = on_every_domain("retreat:arena");
  auto bridge = on_every_domain("retreat:bridge");
  auto status = bridge->create_reader<wire::AgentStatus>({wire::agent_status_topic("retreat"), control});
  auto telemetry = bridge->create_reader<wire::ArenaTelemetry>({wire::arena_telemetry_topic("retreat"), control});
  auto watch = on_domain(first_domain + 1, "a watcher on the second domain");
  auto watched = watch->create_reader<wire::ArenaTelemetry>({wire::arena_telemetry_topic("retreat"), control});

  // Agents of robots 0, 1 and 2 (one per domain) publish their status: the bridge hears each once.
  std::vector<std::unique_ptr<Transport>> agents;
  std::vector<Writer<wire::AgentStatus>> writers;
  for (wire::RobotId r = 0; r < 3; ++r) {
    agents.push_back(on_domain(wire::robot_domain(first_domain, domains, r), "agent " + std::to_string(r)));
    writers.push_back(agents.back()->create_writer<wire::AgentStatus>({wire::agent_status_topic("retreat"), control}));
    wire::AgentStatus s;
    s.robot_id = r;
    ASSERT_EQ(writers.back().write(s), WriteResult::ok);
  }
  auto heard = status.take();
  ASSERT_EQ(heard.size(), 3u);
  std::sort(heard.begin(), heard.end(), [](const auto& a, const auto& b) { return a.robot_id < b.robot_id; });
  for (wire::RobotId r = 0; r < 3; ++r) EXPECT_EQ(heard[r].robot_id, r);

  // The arena's telemetry goes out once, on the first domain.
  auto telemetry_writer = arena->create_writer<wire::ArenaTelemetry>({wire::arena_telemetry_topic("retreat"), control});
  ASSERT_EQ(telemetry_writer.write({}), WriteResult::ok);
  EXPECT_EQ(telemetry.take().size(), 1u) << "not once per domain";
  EXPECT_TRUE(watched.take().empty());

  // Every domain's participants are seen.
  const auto seen = bridge->participants();
  for (wire::RobotId r = 0; r < 3; ++r) {
    EXPECT_TRUE(std::any_of(seen.begin(), seen.end(), [&](const auto& p) { return p.user_data == "agent " + std::to_string(r); }))
        << "agent " << r;
  }
}

TEST(ShardedTransport, DomainsOutsideTheRangeAreRefusedNamingTheValue) {
  const auto refusal = [](int domain, int count) -> std::string {
    ParticipantOptions options{domain, "x", "x", ""};
    options.domains = count;
    try {
      make_transport("inmemory", options);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(refusal(0, 0).find("dds.domains = 0: must be an integer in 1..64"), std::string::npos) << refusal(0, 0);
  EXPECT_NE(refusal(0, 65).find("dds.domains = 65"), std::string::npos);
  EXPECT_NE(refusal(230, 4).find("dds.domains = 4: must be an integer in 1..3"), std::string::npos) << refusal(230, 4);
  EXPECT_EQ(refusal(230, 3), "");
}

}  // namespace
}  // namespace retreat::transport
