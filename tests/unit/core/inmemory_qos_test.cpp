// The in-memory transport's QoS matching rules, which mirror the DDS rules retreat relies on
// (idl/transport/include/retreat/transport/inmemory.hpp): same topic and type; a best-effort
// writer does not match a reliable reader; a volatile writer does not match a transient-local
// reader; transient-local writers replay the last `depth` samples per instance to late readers.

#include <gtest/gtest.h>

#include <thread>

#include "retreat/testing/process.hpp"
#include "retreat/transport/inmemory.hpp"

namespace retreat::transport {
namespace {

using namespace std::chrono_literals;

constexpr QosIntent reliable_volatile{Reliability::reliable, Durability::volatile_data, 0};
constexpr QosIntent best_effort_volatile{Reliability::best_effort, Durability::volatile_data, 0};
constexpr QosIntent reliable_transient{Reliability::reliable, Durability::transient_local, 1};
constexpr QosIntent best_effort_transient{Reliability::best_effort, Durability::transient_local, 1};

class InMemoryQos : public ::testing::Test {
 protected:
  std::shared_ptr<InMemoryBus> bus_ = make_inmemory_bus();
  std::unique_ptr<Transport> a_ = make_inmemory_transport(bus_, {0, "a", "retreat:test:a", ""});
  std::unique_ptr<Transport> b_ = make_inmemory_transport(bus_, {0, "b", "retreat:test:b", ""});

  /// Whether a writer with `w` and a reader with `r` on one topic match, and whether a sample
  /// written after both exist arrives.
  bool matches(QosIntent w, QosIntent r) {
    const std::string topic = "t/robot_1/proximity";
    auto writer = a_->create_writer<wire::ProximityFrame>({topic, w});
    auto reader = b_->create_reader<wire::ProximityFrame>({topic, r});
    const bool matched = writer.matched_count() == 1 && reader.matched_count() == 1;
    EXPECT_EQ(writer.write({1, 0, 0.0, wire::Phase::inside, false, 0}), WriteResult::ok);
    const bool delivered = reader.take().size() == 1;
    EXPECT_EQ(matched, delivered) << "a match must mean delivery and no match no delivery";
    return matched && delivered;
  }
};

TEST_F(InMemoryQos, TheIntentsOfTheProtocolAreWhatTheDocumentationSays) {
  EXPECT_EQ(QosIntent::control(), reliable_volatile);
  EXPECT_EQ(QosIntent::state(), reliable_transient);
}

TEST_F(InMemoryQos, ReliableWriterMatchesReliableAndBestEffortReaders) {
  EXPECT_TRUE(matches(reliable_volatile, reliable_volatile));
  EXPECT_TRUE(matches(reliable_volatile, best_effort_volatile));
}

TEST_F(InMemoryQos, BestEffortWriterDoesNotMatchAReliableReader) {
  EXPECT_FALSE(matches(best_effort_volatile, reliable_volatile));
  EXPECT_TRUE(matches(best_effort_volatile, best_effort_volatile));
}

TEST_F(InMemoryQos, VolatileWriterDoesNotMatchATransientLocalReader) {
  EXPECT_FALSE(matches(reliable_volatile, reliable_transient));
  EXPECT_TRUE(matches(reliable_transient, reliable_volatile));
  EXPECT_TRUE(matches(reliable_transient, reliable_transient));
}

TEST_F(InMemoryQos, BothRulesApplyTogether) {
  EXPECT_FALSE(matches(best_effort_transient, reliable_transient));
  EXPECT_TRUE(matches(best_effort_transient, best_effort_transient));
  EXPECT_FALSE(matches(best_effort_volatile, best_effort_transient));
}

TEST_F(InMemoryQos, SameTopicNameWithAnotherTypeDoesNotMatch) {
  auto writer = a_->create_writer<wire::Decision>({"t/robot_1/x", QosIntent::control()});
  auto reader = b_->create_reader<wire::ProximityFrame>({"t/robot_1/x", QosIntent::control()});
  EXPECT_EQ(writer.matched_count(), 0u);
  EXPECT_EQ(reader.matched_count(), 0u);
  EXPECT_EQ(writer.write({1, 0, 0.0, false}), WriteResult::ok);
  EXPECT_TRUE(reader.take().empty());
}

TEST_F(InMemoryQos, AnotherTopicNameDoesNotMatch) {
  auto writer =
      a_->create_writer<wire::ProximityFrame>({"t/robot_1/proximity", QosIntent::control()});
  auto reader =
      b_->create_reader<wire::ProximityFrame>({"t/robot_2/proximity", QosIntent::control()});
  EXPECT_EQ(writer.matched_count(), 0u);
  EXPECT_EQ(reader.matched_count(), 0u);
}

TEST_F(InMemoryQos, ALateTransientLocalReaderGetsTheLastDepthSamplesOfEveryInstance) {
  auto writer = a_->create_writer<wire::AgentStatus>(
      {"t/agent_status", {Reliability::reliable, Durability::transient_local, 2}});
  for (std::uint32_t robot = 1; robot <= 3; ++robot) {
    for (std::int64_t tick = 0; tick < 5; ++tick) {
      wire::AgentStatus s;
      s.robot_id = robot;
      s.tick = tick;
      ASSERT_EQ(writer.write(s), WriteResult::ok);
    }
  }
  auto reader = b_->create_reader<wire::AgentStatus>({"t/agent_status", QosIntent::state()});
  const auto got = reader.take();
  ASSERT_EQ(got.size(), 6u);  // 3 instances x depth 2
  for (const auto& s : got) EXPECT_GE(s.tick, 3) << "robot " << s.robot_id;
}

TEST_F(InMemoryQos, ALateVolatileReaderGetsNothingThatWasWrittenBefore) {
  auto writer = a_->create_writer<wire::AgentStatus>({"t/agent_status", QosIntent::state()});
  ASSERT_EQ(writer.write({}), WriteResult::ok);
  auto reader = b_->create_reader<wire::AgentStatus>(
      {"t/agent_status", {Reliability::reliable, Durability::volatile_data, 1}});
  EXPECT_EQ(reader.matched_count(), 1u);
  EXPECT_TRUE(reader.take().empty());
}

TEST_F(InMemoryQos, ADroppedWriterIsNoLongerMatched) {
  auto reader =
      b_->create_reader<wire::ProximityFrame>({"t/robot_1/proximity", QosIntent::control()});
  {
    auto writer =
        a_->create_writer<wire::ProximityFrame>({"t/robot_1/proximity", QosIntent::control()});
    EXPECT_EQ(reader.matched_count(), 1u);
  }
  EXPECT_EQ(reader.matched_count(), 0u);
}

// wake() ends a wait() of another thread as a sample would (an agent's stop signal), and
// a wake() before the wait() is not lost.
TEST_F(InMemoryQos, WakeEndsAWaitOnAnotherThreadAndIsNotLostWhenItComesFirst) {
  b_->wake();
  EXPECT_TRUE(b_->wait(0s)) << "a wake before the wait is kept";
  EXPECT_FALSE(b_->wait(0s)) << "and counted once";
  std::thread waker([this] { b_->wake(); });
  // The ceiling only bounds a failure; the wake ends the wait long before.
  EXPECT_TRUE(b_->wait(retreat::testing::hang_ceiling));
  waker.join();
}

TEST_F(InMemoryQos, MatchedEndpointsNameTheRemoteParticipant) {
  auto writer =
      a_->create_writer<wire::ProximityFrame>({"t/robot_1/proximity", QosIntent::control()});
  auto reader =
      b_->create_reader<wire::ProximityFrame>({"t/robot_1/proximity", QosIntent::control()});
  ASSERT_EQ(reader.matched().size(), 1u);
  EXPECT_EQ(reader.matched()[0].participant_guid, a_->guid());
  ASSERT_EQ(writer.matched().size(), 1u);
  EXPECT_EQ(writer.matched()[0].participant_guid, b_->guid());
}

// A writer resolves its topic once and keeps the list of readers it delivers to; that list must
// follow the topic: readers that join after the writer has written get what follows, readers
// that leave get nothing more, and the remaining ones lose nothing. On a shared bus and on a
// confined one (one thread, no locks: what run_in_memory uses).
class InMemoryRoutes : public ::testing::TestWithParam<Threading> {
 protected:
  std::shared_ptr<InMemoryBus> bus_ = make_inmemory_bus(GetParam());
  std::unique_ptr<Transport> a_ = make_inmemory_transport(bus_, {0, "a", "retreat:test:a", ""});
  std::unique_ptr<Transport> b_ = make_inmemory_transport(bus_, {0, "b", "retreat:test:b", ""});
};

TEST_P(InMemoryRoutes, AWritersReadersFollowTheTopicAfterItHasWritten) {
  const TopicSpec topic{"t/robot_1/proximity", QosIntent::control()};
  auto writer = a_->create_writer<wire::ProximityFrame>(topic);
  auto first = b_->create_reader<wire::ProximityFrame>(topic);
  ASSERT_EQ(writer.write({1, 1, 0.03, wire::Phase::inside, false, 0}), WriteResult::ok);
  std::vector<wire::ProximityFrame> got;
  {
    auto second = b_->create_reader<wire::ProximityFrame>(topic);
    ASSERT_EQ(writer.write({1, 2, 0.06, wire::Phase::inside, false, 1}), WriteResult::ok);
    second.take(got);
    ASSERT_EQ(got.size(), 1u);  // only what was written after it joined
    EXPECT_EQ(got[0].tick, 2);
  }
  ASSERT_EQ(writer.write({1, 3, 0.09, wire::Phase::inside, false, 0}), WriteResult::ok);
  EXPECT_TRUE(b_->wait(0ns));
  first.take(got);
  ASSERT_EQ(got.size(), 3u);
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].tick, static_cast<std::int64_t>(i + 1));
  EXPECT_EQ(got[1].new_onsets, 1u);
  first.take(got);
  EXPECT_TRUE(got.empty()) << "take(out) clears out";
  EXPECT_FALSE(b_->wait(0ns)) << "nothing arrived since the last wait";
}

TEST_P(InMemoryRoutes, ADroppedWriterDeliversNothingAndItsTopicStaysUsable) {
  const TopicSpec topic{"t/robot_2/decision", QosIntent::control()};
  auto reader = b_->create_reader<wire::Decision>(topic);
  {
    auto writer = a_->create_writer<wire::Decision>(topic);
    ASSERT_EQ(writer.write({2, 1, 0.03, false}), WriteResult::ok);
  }
  auto again = a_->create_writer<wire::Decision>(topic);
  ASSERT_EQ(again.write({2, 2, 0.06, true}), WriteResult::ok);
  const auto got = reader.take();
  ASSERT_EQ(got.size(), 2u);
  EXPECT_FALSE(got[0].retreat);
  EXPECT_TRUE(got[1].retreat);
  EXPECT_EQ(reader.matched_count(), 1u);
}

// An inbox holds its first sample inside itself and the rest in a queue; full, it drops the
// oldest, wherever that one is, and counts it. Locked or not, the order is arrival order.
TEST_P(InMemoryRoutes, AFullInboxDropsTheOldestAndCountsIt) {
  Inbox inbox(std::make_shared<Notifier>(GetParam()), 2);
  const auto frame = [](std::int64_t tick) {
    return wire::AnyMessage{wire::ProximityFrame{1, tick, 0.03 * static_cast<double>(tick), wire::Phase::inside, false, 0}};
  };
  const auto ticks = [&] {
    std::vector<std::int64_t> out;
    inbox.drain([&](wire::AnyMessage&& m) { out.push_back(std::get<wire::ProximityFrame>(m).tick); });
    return out;
  };
  for (std::int64_t k = 1; k <= 3; ++k) inbox.push(frame(k));  // 1 was the one inside the inbox
  EXPECT_EQ(inbox.overflowed(), 1u);
  EXPECT_FALSE(inbox.empty());
  EXPECT_EQ(ticks(), (std::vector<std::int64_t>{2, 3}));
  EXPECT_TRUE(inbox.empty());
  for (std::int64_t k = 4; k <= 7; ++k) inbox.push(frame(k));  // then 4 and 5, from both places
  EXPECT_EQ(inbox.overflowed(), 3u);
  EXPECT_EQ(ticks(), (std::vector<std::int64_t>{6, 7}));
  inbox.push(frame(8));
  EXPECT_EQ(ticks(), (std::vector<std::int64_t>{8}));
  EXPECT_EQ(ticks(), (std::vector<std::int64_t>{}));
}

std::string threading_name(const ::testing::TestParamInfo<Threading>& param) {
  return param.param == Threading::shared ? "Shared" : "Confined";
}

INSTANTIATE_TEST_SUITE_P(Threading, InMemoryRoutes, ::testing::Values(Threading::shared, Threading::confined),
                         threading_name);

}  // namespace
}  // namespace retreat::transport
