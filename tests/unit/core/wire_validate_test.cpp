// retreat::wire::validate: what a receiver drops and counts (docs/protocol.md, "Validation").
// Every fault of every message kind, and the order in which faults are reported.

#include <gtest/gtest.h>

#include <limits>

#include "retreat/wire/validate.hpp"

namespace retreat::wire {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr float fnan = std::numeric_limits<float>::quiet_NaN();

ProximityFrame frame() { return {3, 10, 0.3, Phase::inside, true, 2}; }
Decision decision() { return {3, 10, 0.3, true}; }
AgentStatus status() { return {3, 10, 0.3, true, false, 4, 0.5, 0.01, 0}; }
ArenaTelemetry telemetry() { return {0, 10, 0.3, 5, 2, 1, 0, 0, 0.4, 7, 900.0}; }
Poses poses() {
  Poses p{
      0, 10, 0.3, {{1, 0.1f, -0.2f, 1.5f, Phase::inside, true}}, {{0.5f, 0.5f}}, {{-0.5f, 0.5f}}};
  return p;
}

TEST(Validate, WellFormedSamplesOfEveryKindPass) {
  EXPECT_EQ(validate(frame(), 3u), SampleFault::ok);
  EXPECT_EQ(validate(decision(), 3u), SampleFault::ok);
  EXPECT_EQ(validate(status(), std::nullopt), SampleFault::ok);
  EXPECT_EQ(validate(telemetry(), std::nullopt), SampleFault::ok);
  EXPECT_EQ(validate(poses(), std::nullopt), SampleFault::ok);
}

TEST(Validate, TimeZeroAndTickZeroAreValid) {
  auto f = frame();
  f.tick = 0;
  f.time = 0.0;
  EXPECT_EQ(validate(f, 3u), SampleFault::ok);
}

TEST(Validate, ARobotIdOtherThanTheTopicsRobotIsDropped) {
  EXPECT_EQ(validate(frame(), 4u), SampleFault::wrong_robot);
  EXPECT_EQ(validate(decision(), 4u), SampleFault::wrong_robot);
  EXPECT_EQ(validate(status(), 4u), SampleFault::wrong_robot);
}

TEST(Validate, OnSharedTopicsAnyRobotIdIsAllowed) {
  auto s = status();
  s.robot_id = 999;
  EXPECT_EQ(validate(s, std::nullopt), SampleFault::ok);
  EXPECT_EQ(validate(frame(), std::nullopt), SampleFault::ok);
}

TEST(Validate, NanInfiniteOrNegativeTimeIsDroppedForEveryKind) {
  for (const double t : {nan, inf, -inf, -0.001}) {
    auto f = frame();
    f.time = t;
    auto d = decision();
    d.time = t;
    auto s = status();
    s.time = t;
    auto a = telemetry();
    a.time = t;
    auto p = poses();
    p.time = t;
    EXPECT_EQ(validate(f, 3u), SampleFault::bad_time) << t;
    EXPECT_EQ(validate(d, 3u), SampleFault::bad_time) << t;
    EXPECT_EQ(validate(s, 3u), SampleFault::bad_time) << t;
    EXPECT_EQ(validate(a, std::nullopt), SampleFault::bad_time) << t;
    EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_time) << t;
  }
}

TEST(Validate, ANegativeTickIsDroppedForEveryKind) {
  auto f = frame();
  f.tick = -1;
  auto d = decision();
  d.tick = -1;
  auto s = status();
  s.tick = -1;
  auto a = telemetry();
  a.tick = std::numeric_limits<std::int64_t>::min();
  auto p = poses();
  p.tick = -5;
  EXPECT_EQ(validate(f, 3u), SampleFault::bad_tick);
  EXPECT_EQ(validate(d, 3u), SampleFault::bad_tick);
  EXPECT_EQ(validate(s, 3u), SampleFault::bad_tick);
  EXPECT_EQ(validate(a, std::nullopt), SampleFault::bad_tick);
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_tick);
}

TEST(Validate, APhaseOctetOutOfRangeIsDropped) {
  auto f = frame();
  f.phase = static_cast<Phase>(3);
  EXPECT_EQ(validate(f, 3u), SampleFault::ok);
  for (const int octet : {4, 9, 255}) {
    f.phase = static_cast<Phase>(octet);
    EXPECT_EQ(validate(f, 3u), SampleFault::bad_phase) << octet;
  }
  auto p = poses();
  p.robots[0].phase = static_cast<Phase>(4);
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_phase);
}

TEST(Validate, NonFiniteOrNegativeEstimatesInAgentStatusAreDropped) {
  for (const double v : {nan, inf, -0.5}) {
    auto s = status();
    s.lambda_hat = v;
    EXPECT_EQ(validate(s, 3u), SampleFault::bad_value) << "lambda_hat " << v;
    s = status();
    s.epsilon = v;
    EXPECT_EQ(validate(s, 3u), SampleFault::bad_value) << "epsilon " << v;
  }
}

TEST(Validate, NonFiniteOrNegativeRatesInTelemetryAreDropped) {
  for (const double v : {nan, inf, -1.0}) {
    auto a = telemetry();
    a.true_density = v;
    EXPECT_EQ(validate(a, std::nullopt), SampleFault::bad_value) << "true_density " << v;
    a = telemetry();
    a.ticks_per_second = v;
    EXPECT_EQ(validate(a, std::nullopt), SampleFault::bad_value) << "ticks_per_second " << v;
  }
}

TEST(Validate, NonFiniteCoordinatesInPosesAreDropped) {
  auto p = poses();
  p.robots[0].x = fnan;
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_value);
  p = poses();
  p.robots[0].theta = std::numeric_limits<float>::infinity();
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_value);
  p = poses();
  p.pickups[0].y = fnan;
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_value);
  p = poses();
  p.dropoffs[0].x = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(validate(p, std::nullopt), SampleFault::bad_value);
}

TEST(Validate, TheWrongRobotIsReportedBeforeAnyOtherFault) {
  auto f = frame();
  f.robot_id = 8;
  f.tick = -1;
  f.time = nan;
  f.phase = static_cast<Phase>(9);
  EXPECT_EQ(validate(f, 3u), SampleFault::wrong_robot);
  f.robot_id = 3;
  EXPECT_EQ(validate(f, 3u), SampleFault::bad_tick);  // then the tick, then the time
  f.tick = 1;
  EXPECT_EQ(validate(f, 3u), SampleFault::bad_time);
  f.time = 1.0;
  EXPECT_EQ(validate(f, 3u), SampleFault::bad_phase);
}

TEST(SampleFaultNames, AreStable) {
  EXPECT_EQ(to_string(SampleFault::ok), "ok");
  EXPECT_EQ(to_string(SampleFault::wrong_robot), "wrong_robot");
  EXPECT_EQ(to_string(SampleFault::bad_time), "bad_time");
  EXPECT_EQ(to_string(SampleFault::bad_tick), "bad_tick");
  EXPECT_EQ(to_string(SampleFault::bad_phase), "bad_phase");
  EXPECT_EQ(to_string(SampleFault::bad_value), "bad_value");
}

}  // namespace
}  // namespace retreat::wire
