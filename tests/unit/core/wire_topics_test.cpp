// retreat::wire topic names, prefixes and type names (docs/protocol.md, "Topics").

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "retreat/wire/messages.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::wire {
namespace {

TEST(TopicNames, PerRobotTopicsCarryThePrefixAndTheRobotId) {
  EXPECT_EQ(proximity_topic("retreat", 0), "retreat/robot_0/proximity");
  EXPECT_EQ(decision_topic("retreat", 17), "retreat/robot_17/decision");
  EXPECT_EQ(proximity_topic("lab/swarm_2", 4294967295u), "lab/swarm_2/robot_4294967295/proximity");
}

TEST(TopicNames, SharedTopicsCarryOnlyThePrefix) {
  EXPECT_EQ(agent_status_topic("retreat"), "retreat/agent_status");
  EXPECT_EQ(arena_telemetry_topic("retreat"), "retreat/arena_telemetry");
  EXPECT_EQ(poses_topic("lab/x"), "lab/x/poses");
}

TEST(TopicNames, TheDefaultPrefixIsRetreat) { EXPECT_STREQ(default_prefix, "retreat"); }

TEST(RobotOfTopic, ReadsTheRobotIdBackFromEveryPerRobotTopic) {
  for (const RobotId id : {0u, 1u, 42u, 4294967295u}) {
    EXPECT_EQ(robot_of_topic(proximity_topic("retreat", id)), id);
    EXPECT_EQ(robot_of_topic(decision_topic("a/b", id)), id);
  }
}

TEST(RobotOfTopic, SharedTopicsBelongToNoRobot) {
  EXPECT_EQ(robot_of_topic(agent_status_topic("retreat")), std::nullopt);
  EXPECT_EQ(robot_of_topic(arena_telemetry_topic("retreat")), std::nullopt);
  EXPECT_EQ(robot_of_topic(poses_topic("retreat")), std::nullopt);
}

TEST(RobotOfTopic, MalformedNamesBelongToNoRobot) {
  for (const char* name : {
           "",                                   // empty
           "retreat/robot_/proximity",           // no digits
           "retreat/robot_x/proximity",          // not a number
           "retreat/robot_-1/proximity",         // negative
           "retreat/robot_3x/proximity",         // trailing garbage in the id
           "retreat/robot_3",                    // no leaf after the id
           "robot_3/proximity",                  // no '/' before robot_
           "retreat/robot_4294967296/decision",  // does not fit a 32-bit robot id
           "retreat/robot_99999999999999999999/decision",
       }) {
    EXPECT_EQ(robot_of_topic(name), std::nullopt) << name;
  }
}

TEST(RobotOfTopic, TheLastRobotSegmentCounts) {
  // A prefix may itself contain "robot_<n>" segments; the per-robot part is the last one.
  EXPECT_EQ(robot_of_topic("site/robot_1/retreat/robot_2/proximity"), 2u);
}

TEST(Prefix, AcceptsWordCharactersAndInnerSlashes) {
  for (const char* p : {"retreat", "a", "lab/swarm_2", "A_b/C9/d", "_"})
    EXPECT_TRUE(is_valid_prefix(p)) << p;
  EXPECT_TRUE(is_valid_prefix(std::string(64, 'a')));
}

TEST(Prefix, RejectsEmptyTooLongAndBadCharacters) {
  for (const char* p : {"", "/retreat", "retreat/", "re//treat", "re treat", "re-treat", "re.treat",
                        "rt/retreat?", "ré"}) {
    EXPECT_FALSE(is_valid_prefix(p)) << p;
  }
  EXPECT_FALSE(is_valid_prefix(std::string(65, 'a')));
}

TEST(TypeNames, AreTheIdlNamesSharedByBothVendors) {
  EXPECT_EQ(type_name(MessageKind::proximity_frame), "retreat::msg::ProximityFrame");
  EXPECT_EQ(type_name(MessageKind::decision), "retreat::msg::Decision");
  EXPECT_EQ(type_name(MessageKind::agent_status), "retreat::msg::AgentStatus");
  EXPECT_EQ(type_name(MessageKind::arena_telemetry), "retreat::msg::ArenaTelemetry");
  EXPECT_EQ(type_name(MessageKind::poses), "retreat::msg::Poses");
}

TEST(TypeNames, KindOfMapsEveryStructToItsKind) {
  static_assert(KindOf<ProximityFrame>::value == MessageKind::proximity_frame);
  static_assert(KindOf<Decision>::value == MessageKind::decision);
  static_assert(KindOf<AgentStatus>::value == MessageKind::agent_status);
  static_assert(KindOf<ArenaTelemetry>::value == MessageKind::arena_telemetry);
  static_assert(KindOf<Poses>::value == MessageKind::poses);
  // The variant lists the kinds in IDL order.
  EXPECT_EQ(AnyMessage(Decision{}).index(), static_cast<std::size_t>(MessageKind::decision));
  EXPECT_EQ(AnyMessage(Poses{}).index(), static_cast<std::size_t>(MessageKind::poses));
}

TEST(Phase, OctetValuesAreThoseOfTheProtocol) {
  EXPECT_EQ(static_cast<int>(Phase::waiting), 0);
  EXPECT_EQ(static_cast<int>(Phase::inside), 1);
  EXPECT_EQ(static_cast<int>(Phase::retreating), 2);
  EXPECT_EQ(static_cast<int>(Phase::departed), 3);
  EXPECT_EQ(phase_count, 4);
  EXPECT_EQ(to_string(Phase::retreating), "retreating");
  EXPECT_EQ(to_string(static_cast<Phase>(7)), "invalid");
}

}  // namespace
}  // namespace retreat::wire
