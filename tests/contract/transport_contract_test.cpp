// One contract suite, compiled once per transport implementation (RETREAT_CONTRACT_VENDOR):
// every implementation must behave the same way for everything retreat relies on.
// Each test runs on its own domain id and with its own topic prefix.

#include <gtest/gtest.h>
#include <dirent.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>

#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/testing/samples.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat::transport {
namespace {

using namespace std::chrono_literals;
using testing::eventually;

constexpr std::string_view vendor = RETREAT_CONTRACT_VENDOR;

std::string test_name() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::string(vendor) + "." + info->test_suite_name() + "." + info->name();
}

int test_domain() {
  // Every suite's domain ids are in retreat/testing/domains.hpp (why: see there).
  return testing::domain_for_test(test_name(), testing::domains::contract.first, testing::domains::contract.count);
}

std::string test_prefix() {
  std::string p = "contract_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name());
  return p;
}

std::unique_ptr<Transport> participant(const std::string& name) {
  ParticipantOptions options;
  options.domain_id = test_domain();
  options.name = name;
  options.user_data = "retreat:test:" + name;
  return make_transport(vendor, options);
}

template <class M>
std::vector<M> receive(Reader<M>& reader, Transport& transport, std::size_t count,
                       std::chrono::milliseconds timeout = retreat::testing::hang_ceiling) {
  std::vector<M> got;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (got.size() < count && std::chrono::steady_clock::now() < deadline) {
    transport.wait(50ms);
    for (auto& m : reader.take()) got.push_back(std::move(m));
  }
  return got;
}

template <class W, class R>
void await_match(W& writer, R& reader) {
  ASSERT_TRUE(eventually([&] { return writer.matched_count() >= 1 && reader.matched_count() >= 1; }, retreat::testing::hang_ceiling))
      << "writer and reader on '" << writer.topic() << "' never matched";
}

std::size_t thread_count() {
  std::size_t n = 0;
  if (DIR* dir = opendir("/proc/self/task")) {
    while (const dirent* e = readdir(dir)) n += e->d_name[0] != '.';
    closedir(dir);
  }
  return n;
}

template <class M, class Make>
void expect_round_trip(Make make, const std::string& topic, QosIntent qos) {
  auto a = participant("writer");
  auto b = participant("reader");
  auto writer = a->create_writer<M>({topic, qos});
  auto reader = b->create_reader<M>({topic, qos});
  await_match(writer, reader);
  for (int i = 1; i <= 3; ++i) ASSERT_EQ(writer.write(make(i)), WriteResult::ok);
  const auto got = receive(reader, *b, 3);
  ASSERT_EQ(got.size(), 3u);
  for (int i = 1; i <= 3; ++i) EXPECT_EQ(got[static_cast<std::size_t>(i - 1)], make(i));
}

TEST(TransportContract, DeliversEveryMessageKindWithIdenticalContents) {
  const auto prefix = test_prefix();
  expect_round_trip<wire::ProximityFrame>([](int i) { return testing::frame_sample(3, i); },
                                          wire::proximity_topic(prefix, 3), QosIntent::control());
  expect_round_trip<wire::Decision>([](int i) { return testing::decision_sample(3, i); },
                                    wire::decision_topic(prefix, 3), QosIntent::control());
  expect_round_trip<wire::AgentStatus>([](int i) { return testing::status_sample(static_cast<std::uint32_t>(i), i); },
                                       wire::agent_status_topic(prefix), QosIntent::state());
  expect_round_trip<wire::ArenaTelemetry>([](int i) { return testing::telemetry_sample(0, i); },
                                          wire::arena_telemetry_topic(prefix), {Reliability::reliable, Durability::transient_local, 8});
  expect_round_trip<wire::Poses>([](int i) { return testing::poses_sample(0, i + 10); },
                                 wire::poses_topic(prefix), {Reliability::reliable, Durability::transient_local, 8});
}

TEST(TransportContract, AReaderForRobotThreeNeverSeesRobotFoursFrames) {
  const auto prefix = test_prefix();
  auto arena = participant("arena");
  auto agent = participant("agent3");
  auto to3 = arena->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 3), QosIntent::control()});
  auto to4 = arena->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 4), QosIntent::control()});
  auto mine = agent->create_reader<wire::ProximityFrame>({wire::proximity_topic(prefix, 3), QosIntent::control()});
  await_match(to3, mine);
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(to4.write(testing::frame_sample(4, i)), WriteResult::ok);
    ASSERT_EQ(to3.write(testing::frame_sample(3, i)), WriteResult::ok);
  }
  ASSERT_TRUE(to3.wait_for_acknowledgments(retreat::testing::hang_ceiling));
  const auto got = receive(*&mine, *agent, 20);
  ASSERT_EQ(got.size(), 20u);
  for (const auto& f : got) EXPECT_EQ(f.robot_id, 3u);
  EXPECT_EQ(to4.matched_count(), 0u) << "robot 4's writer matched robot 3's reader";
  EXPECT_EQ(mine.matched_count(), 1u);
  EXPECT_EQ(mine.stats().dropped_total(), 0u);
}

TEST(TransportContract, KeyedInstancesKeepTheLastSampleOfEachRobot) {
  const auto prefix = test_prefix();
  auto a = participant("agents");
  auto writer = a->create_writer<wire::AgentStatus>({wire::agent_status_topic(prefix), QosIntent::state()});
  for (std::uint32_t robot = 1; robot <= 3; ++robot) {
    for (int i = 0; i < 5; ++i) ASSERT_EQ(writer.write(testing::status_sample(robot, 10 * robot + i)), WriteResult::ok);
  }
  auto b = participant("observer");
  auto reader = b->create_reader<wire::AgentStatus>({wire::agent_status_topic(prefix), QosIntent::state()});
  const auto got = receive(reader, *b, 3);
  ASSERT_EQ(got.size(), 3u);
  std::map<std::uint32_t, wire::AgentStatus> by_robot;
  for (const auto& s : got) by_robot[s.robot_id] = s;
  for (std::uint32_t robot = 1; robot <= 3; ++robot) {
    ASSERT_EQ(by_robot.count(robot), 1u);
    EXPECT_EQ(by_robot[robot], testing::status_sample(robot, 10 * robot + 4));
  }
  // Nothing more arrives: only the last sample per instance was kept.
  b->wait(300ms);
  EXPECT_TRUE(reader.take().empty());
}

TEST(TransportContract, TenThousandReliableSamplesArriveWithNoneLostAndNoneReordered) {
  const auto prefix = test_prefix();
  auto a = participant("arena");
  auto b = participant("agent");
  auto writer = a->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 7), QosIntent::control()});
  auto reader = b->create_reader<wire::ProximityFrame>({wire::proximity_topic(prefix, 7), QosIntent::control()});
  await_match(writer, reader);
  constexpr int count = 10'000;
  for (int i = 0; i < count; ++i) ASSERT_EQ(writer.write(testing::frame_sample(7, i)), WriteResult::ok);
  const auto got = receive(reader, *b, count, retreat::testing::hang_ceiling);
  ASSERT_EQ(got.size(), static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) ASSERT_EQ(got[static_cast<std::size_t>(i)].tick, i) << "reordered or lost at " << i;
}

/// A little-endian value of @p bytes at @p offset.
template <class T>
T little_endian_at(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  T value{};
  std::memcpy(&value, bytes.data() + offset, sizeof value);  // this host is little-endian (x86-64)
  return value;
}

TEST(TransportContract, ARawReaderKeepsEverySampleAsItsCdrBytes) {
  const auto prefix = test_prefix();
  const TopicSpec topic{wire::decision_topic(prefix, 7), QosIntent::control()};
  if (vendor == "inmemory") {
    auto t = participant("recorder");
    EXPECT_THROW(t->create_raw_reader(wire::MessageKind::decision, topic), std::invalid_argument);
    return;
  }
  auto a = participant("agent");
  auto b = participant("recorder");
  auto writer = a->create_writer<wire::Decision>(topic);
  auto reader = b->create_raw_reader(wire::MessageKind::decision, topic);
  await_match(writer, reader);
  constexpr int count = 50;
  for (int i = 0; i < count; ++i) ASSERT_EQ(writer.write(testing::decision_sample(7, i)), WriteResult::ok);
  std::vector<RawSample> got;
  ASSERT_TRUE(eventually([&] { reader.take(got); return got.size() >= count; }, retreat::testing::hang_ceiling))
      << got.size() << " of " << count << " samples";
  ASSERT_EQ(got.size(), static_cast<std::size_t>(count));
  EXPECT_EQ(reader.overflowed(), 0u);
  const auto before = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch()).count();
  for (int i = 0; i < count; ++i) {
    const auto& cdr = got[static_cast<std::size_t>(i)].cdr;
    const auto expected = testing::decision_sample(7, i);
    // XCDR1 little endian (encapsulation 0x0001, options 0), then the @final struct's members at
    // their natural alignment from the end of the header: robot_id at 0, tick at 8, time at 16,
    // retreat at 24 (docs/protocol.md §4).
    ASSERT_GE(cdr.size(), 4u + 25u) << "sample " << i;
    EXPECT_EQ(cdr[0], 0x00);
    EXPECT_EQ(cdr[1], 0x01);
    EXPECT_EQ(little_endian_at<std::uint32_t>(cdr, 4), expected.robot_id);
    EXPECT_EQ(little_endian_at<std::int64_t>(cdr, 12), expected.tick) << "sample " << i;
    EXPECT_EQ(little_endian_at<double>(cdr, 20), expected.time);
    EXPECT_EQ(cdr[28], expected.retreat ? 1 : 0);
    EXPECT_GT(got[static_cast<std::size_t>(i)].source_time_ns, 0);
    EXPECT_LE(got[static_cast<std::size_t>(i)].source_time_ns, before);
  }
}

TEST(TransportContract, ALateJoinerGetsTheLastTransientLocalSample) {
  const auto prefix = test_prefix();
  auto arena = participant("arena");
  auto writer = arena->create_writer<wire::ArenaTelemetry>({wire::arena_telemetry_topic(prefix), QosIntent::state()});
  for (int i = 0; i < 10; ++i) ASSERT_EQ(writer.write(testing::telemetry_sample(0, i)), WriteResult::ok);
  auto bridge = participant("late-bridge");
  auto reader = bridge->create_reader<wire::ArenaTelemetry>({wire::arena_telemetry_topic(prefix), QosIntent::state()});
  const auto got = receive(reader, *bridge, 1);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got.front(), testing::telemetry_sample(0, 9));
}

TEST(TransportContract, AVolatileReaderDoesNotReceiveWhatWasWrittenBeforeItJoined) {
  const auto prefix = test_prefix();
  auto arena = participant("arena");
  auto writer = arena->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 1), QosIntent::control()});
  ASSERT_EQ(writer.write(testing::frame_sample(1, 0)), WriteResult::ok);
  auto agent = participant("agent");
  auto reader = agent->create_reader<wire::ProximityFrame>({wire::proximity_topic(prefix, 1), QosIntent::control()});
  await_match(writer, reader);
  ASSERT_EQ(writer.write(testing::frame_sample(1, 1)), WriteResult::ok);
  const auto got = receive(reader, *agent, 1);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got.front().tick, 1);
}

// run.recorders: an agent's answer writer keeps its answers for a recorder whose reader matches it
// only after the first ones were written (qos.hpp, kept_for_recorders). The recorder's
// transient-local reader gets every one, in order (Cyclone DDS too: its durability service
// history would keep one only); the arena's volatile reader still matches and gets only new ones.
TEST(TransportContract, ARecordedAnswerWriterKeepsEveryAnswerForALateRecorder) {
  const auto prefix = test_prefix();
  const auto topic = wire::decision_topic(prefix, 2);
  auto agent = participant("agent");
  auto writer = agent->create_writer<wire::Decision>({topic, QosIntent::answers().kept_for_recorders(1)});
  constexpr int before = 100;
  for (int i = 0; i < before; ++i) ASSERT_EQ(writer.write(testing::decision_sample(2, i)), WriteResult::ok);
  auto recorder = participant("recorder");
  auto recorded = recorder->create_reader<wire::Decision>(
      {topic, {Reliability::reliable, Durability::transient_local, 0}});
  auto arena = participant("arena");
  auto live = arena->create_reader<wire::Decision>({topic, QosIntent::control()});
  ASSERT_TRUE(eventually([&] { return writer.matched_count() >= 2 && live.matched_count() >= 1; },
                         retreat::testing::hang_ceiling));
  ASSERT_EQ(writer.write(testing::decision_sample(2, before)), WriteResult::ok);
  const auto got = receive(recorded, *recorder, before + 1);
  ASSERT_EQ(got.size(), std::size_t{before + 1});
  for (int i = 0; i <= before; ++i) EXPECT_EQ(got[static_cast<std::size_t>(i)], testing::decision_sample(2, i));
  const auto new_only = receive(live, *arena, 1);
  ASSERT_EQ(new_only.size(), 1u);
  EXPECT_EQ(new_only.front(), testing::decision_sample(2, before));
}

TEST(TransportContract, InvalidSamplesAreDroppedAndCountedNeverPassedOn) {
  const auto prefix = test_prefix();
  auto a = participant("arena");
  auto b = participant("agent");
  auto writer = a->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 3), QosIntent::control()});
  auto reader = b->create_reader<wire::ProximityFrame>({wire::proximity_topic(prefix, 3), QosIntent::control()});
  await_match(writer, reader);
  auto wrong_robot = testing::frame_sample(4, 1);
  auto nan_time = testing::frame_sample(3, 2);
  nan_time.time = std::numeric_limits<double>::quiet_NaN();
  auto negative_time = testing::frame_sample(3, 3);
  negative_time.time = -1.0;
  auto bad_phase = testing::frame_sample(3, 4);
  bad_phase.phase = static_cast<wire::Phase>(9);
  const auto good = testing::frame_sample(3, 5);
  for (const auto& f : {wrong_robot, nan_time, negative_time, bad_phase, good}) {
    ASSERT_EQ(writer.write(f), WriteResult::ok);
  }
  ASSERT_TRUE(writer.wait_for_acknowledgments(retreat::testing::hang_ceiling));
  std::vector<wire::ProximityFrame> got;
  ASSERT_TRUE(eventually([&] {
    b->wait(20ms);
    for (auto& f : reader.take()) got.push_back(f);
    return reader.stats().accepted + reader.stats().dropped_total() >= 5;
  }, retreat::testing::hang_ceiling));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got.front(), good);
  const auto stats = reader.stats();
  EXPECT_EQ(stats.dropped[static_cast<std::size_t>(wire::SampleFault::wrong_robot)], 1u);
  EXPECT_EQ(stats.dropped[static_cast<std::size_t>(wire::SampleFault::bad_time)], 2u);
  EXPECT_EQ(stats.dropped[static_cast<std::size_t>(wire::SampleFault::bad_phase)], 1u);
  EXPECT_EQ(stats.dropped_total(), 4u);
}

TEST(TransportContract, MatchedEndpointsNameTheRemoteWriterAndItsParticipant) {
  const auto prefix = test_prefix();
  auto arena = participant("arena");
  auto agent = participant("agent");
  auto writer = arena->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 2), QosIntent::control()});
  auto reader = agent->create_reader<wire::ProximityFrame>({wire::proximity_topic(prefix, 2), QosIntent::control()});
  await_match(writer, reader);
  const auto endpoints = agent->matched_endpoints();
  ASSERT_EQ(endpoints.size(), 1u);
  EXPECT_TRUE(endpoints.front().is_reader);
  EXPECT_EQ(endpoints.front().topic, wire::proximity_topic(prefix, 2));
  ASSERT_EQ(endpoints.front().remotes.size(), 1u);
  EXPECT_EQ(endpoints.front().remotes.front().participant_guid, arena->guid());
  EXPECT_EQ(endpoints.front().remotes.front().guid.size(), 32u);
}

TEST(TransportContract, DiscoveryShowsEachParticipantsUserDataAndFindsItByGuid) {
  auto arena = participant("arena");
  auto agent = participant("agent-7");
  ASSERT_TRUE(eventually([&] {
    for (const auto& p : arena->participants()) {
      if (p.guid == agent->guid() && p.user_data == "retreat:test:agent-7") return true;
    }
    return false;
  }, retreat::testing::hang_ceiling)) << "the arena never saw the agent's user data";
  // One participant by its GUID (the agent tells a recorder from an arena so): the same record.
  const auto found = arena->participant(agent->guid());
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->user_data, "retreat:test:agent-7");
  EXPECT_EQ(arena->participant(arena->guid())->user_data, "retreat:test:arena");
  EXPECT_FALSE(arena->participant(std::string(32, '0')).has_value());
  const auto gone = agent->guid();
  agent.reset();
  ASSERT_TRUE(eventually([&] { return !arena->participant(gone).has_value(); }, retreat::testing::hang_ceiling))
      << "a participant that left is still found";
}

TEST(TransportContract, DiscoveryListsEveryParticipantOfALargeSwarm) {
  // More participants than one read of the built-in topic used to hold (Cyclone DDS: 256).
  if (vendor == "fastdds") {
    GTEST_SKIP() << "Fast DDS lists what its participant listener saw (no batch); 300 participants of one "
                    "process exceed one domain's port block with the built-in settings";
  }
  constexpr std::size_t crowd = 300;
  std::vector<std::unique_ptr<Transport>> agents;
  for (std::size_t i = 0; i < crowd; ++i) agents.push_back(participant("crowd-" + std::to_string(i)));
  std::size_t seen = 0;
  EXPECT_TRUE(eventually([&] {
    seen = 0;
    for (const auto& p : agents.front()->participants()) seen += p.user_data.rfind("retreat:test:crowd-", 0) == 0;
    return seen == crowd;
  }, retreat::testing::hang_ceiling)) << "saw " << seen << " of " << crowd;
}

TEST(TransportContract, ShutdownLeavesNoThreadBehind) {
  const auto prefix = test_prefix();
  const auto before = thread_count();
  {
    auto a = participant("a");
    auto b = participant("b");
    auto writer = a->create_writer<wire::Decision>({wire::decision_topic(prefix, 1), QosIntent::control()});
    auto reader = b->create_reader<wire::Decision>({wire::decision_topic(prefix, 1), QosIntent::control()});
    await_match(writer, reader);
    ASSERT_EQ(writer.write(testing::decision_sample(1, 1)), WriteResult::ok);
    ASSERT_EQ(receive(reader, *b, 1).size(), 1u);
  }
  // Middleware threads may take a moment to join after the last entity is deleted.
  EXPECT_TRUE(eventually([&] { return thread_count() <= before; }, retreat::testing::hang_ceiling))
      << "threads before: " << before << ", after: " << thread_count();
}

TEST(TransportContract, ADomainIdOutOfRangeIsRefusedWithTheValueAndTheRange) {
  ParticipantOptions options;
  options.domain_id = 233;
  try {
    make_transport(vendor, options);
    FAIL() << "domain 233 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dds.domain = 233: must be an integer in 0..232");
  }
}

TEST(TransportContract, AMissingOrMalformedProfileIsRefusedWithItsPath) {
  if (vendor == "inmemory") GTEST_SKIP() << "the in-memory transport takes no vendor profile";
  ParticipantOptions options;
  options.domain_id = test_domain();
  options.profile = "/nonexistent/profile.xml";
  try {
    make_transport(vendor, options);
    FAIL() << "a missing profile was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dds.profile = '/nonexistent/profile.xml'"), std::string::npos) << e.what();
  }
  const std::string bad = ::testing::TempDir() + "/retreat_bad_profile_" + std::string(vendor) + ".xml";
  std::ofstream(bad) << "<this is not xml";
  options.profile = bad;
  try {
    make_transport(vendor, options);
    FAIL() << "a malformed profile was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

TEST(TransportContract, AnUnknownVendorNameIsRefusedWithTheAllowedNames) {
  try {
    make_transport("opensplice", {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--dds 'opensplice': must be one of"), std::string::npos) << what;
    EXPECT_NE(what.find(std::string(vendor)), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace retreat::transport
