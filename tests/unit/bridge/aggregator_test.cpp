// retreat::telemetry::Aggregator: scripted samples in, exact numbers out.

#include "retreat/telemetry/aggregator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace retreat::telemetry {
namespace {

/// λ* = 1 robot/m², |D| = 4 m², status every 1 s: the histogram's bins are 0.25 wide
/// (12 bins over [0, 3)), a status is stale 3·1 + 1 = 4 s behind the telemetry.
RunInfo unit_run() {
  RunInfo r;
  r.scenario = "scripted";
  r.area = 4.0;
  r.lambda_star = 1.0;
  r.status_period = 1.0;
  return r;
}

wire::ArenaTelemetry telemetry_at(double time, std::uint32_t inside, std::int64_t tick = -1) {
  wire::ArenaTelemetry t;
  t.tick = tick >= 0 ? tick : static_cast<std::int64_t>(std::llround(time / 0.03));
  t.time = time;
  t.inside = inside;
  t.waiting = 2;
  t.retreating = 1;
  t.departed = 3;
  t.lost_agents = 0;
  t.true_density = inside / 4.0;
  t.deliveries = 10 * inside;
  t.ticks_per_second = 1000.0;
  return t;
}

wire::AgentStatus status(wire::RobotId robot, double lambda_hat, double time = 10.0, bool deciding = true,
                         bool retreating = false, std::int64_t tick = 100) {
  wire::AgentStatus s;
  s.robot_id = robot;
  s.tick = tick;
  s.time = time;
  s.deciding = deciding;
  s.retreating = retreating;
  s.onsets_in_window = 7;
  s.lambda_hat = lambda_hat;
  s.epsilon = 0.01;
  return s;
}

TEST(Aggregator, StartsWithNoTelemetryAndAnEmptyHistogram) {
  Aggregator a(unit_run());
  const auto s = a.snapshot();
  EXPECT_FALSE(s.telemetry.has_value());
  EXPECT_FALSE(s.poses.has_value());
  EXPECT_TRUE(s.agents.empty());
  EXPECT_EQ(s.runs, 0u);
  EXPECT_EQ(s.version, 0u);
  EXPECT_EQ(s.history_size, 0u);
  ASSERT_EQ(s.estimates.counts.size(), 12u);
  EXPECT_DOUBLE_EQ(s.estimates.bin_width, 0.25);
  EXPECT_EQ(s.estimates.count, 0u);
  EXPECT_TRUE(std::isnan(s.estimates.mean()));
  EXPECT_DOUBLE_EQ(s.run.optimal_population(), 4.0);
}

TEST(Aggregator, KeepsTheNewestTelemetryAndAppendsOnePointPerSample) {
  Aggregator a(unit_run());
  a.on_telemetry(telemetry_at(0.0, 3));
  a.on_telemetry(telemetry_at(0.1, 4));
  a.on_telemetry(telemetry_at(0.2, 5));
  const auto s = a.snapshot();
  ASSERT_TRUE(s.telemetry.has_value());
  EXPECT_EQ(s.telemetry->inside, 5u);
  EXPECT_EQ(s.runs, 1u);
  EXPECT_EQ(s.version, 3u);
  EXPECT_EQ(s.samples.telemetry, 3u);
  ASSERT_EQ(a.history().size(), 3u);
  EXPECT_EQ(a.history()[0].inside, 3u);
  EXPECT_EQ(a.history()[2].inside, 5u);
  EXPECT_EQ(a.history()[2].deliveries, 50u);
  EXPECT_DOUBLE_EQ(a.history()[2].true_density, 1.25);
  ASSERT_TRUE(s.last_point.has_value());
  EXPECT_DOUBLE_EQ(s.last_point->time, 0.2);
}

TEST(Aggregator, BinsTheEstimatesOfDecidingAgentsOnly) {
  Aggregator a(unit_run());
  a.on_status(status(0, 0.1));                       // bin 0
  a.on_status(status(1, 1.0));                       // bin 4: [1.0, 1.25)
  a.on_status(status(2, 2.99));                      // bin 11
  a.on_status(status(3, 3.0));                       // beyond 3λ*: overflow
  a.on_status(status(4, 0.5, 10.0, false));          // not deciding yet: not counted
  a.on_status(status(5, 0.5, 10.0, true, true));     // retreating: not counted
  const auto h = a.estimates();
  EXPECT_EQ(h.count, 4u);
  EXPECT_EQ(h.counts[0], 1u);
  EXPECT_EQ(h.counts[4], 1u);
  EXPECT_EQ(h.counts[11], 1u);
  EXPECT_EQ(h.overflow, 1u);
  std::uint32_t total = 0;
  for (auto c : h.counts) total += c;
  EXPECT_EQ(total, 3u);
  EXPECT_DOUBLE_EQ(h.sum, 0.1 + 1.0 + 2.99 + 3.0);
  EXPECT_DOUBLE_EQ(h.mean(), (0.1 + 1.0 + 2.99 + 3.0) / 4);
  EXPECT_DOUBLE_EQ(h.min, 0.1);
  EXPECT_DOUBLE_EQ(h.max, 3.0);
  const auto s = a.snapshot();
  ASSERT_EQ(s.agents.size(), 6u);
  EXPECT_TRUE(s.agents[0].counted);
  EXPECT_FALSE(s.agents[4].counted);
  EXPECT_FALSE(s.agents[5].counted);
}

TEST(Aggregator, AStatusMoreThanThreeStatusPeriodsAndASecondBehindTheArenaIsStale) {
  Aggregator a(unit_run());
  a.on_telemetry(telemetry_at(100.0, 4));
  a.on_status(status(0, 1.0, 95.9));  // 4.1 s behind: stale
  a.on_status(status(1, 1.0, 96.0));  // 4.0 s behind: counted
  const auto s = a.snapshot();
  EXPECT_FALSE(s.agents[0].counted);
  EXPECT_TRUE(s.agents[1].counted);
  EXPECT_EQ(s.estimates.count, 1u);
}

TEST(Aggregator, PosesWithRobotsRestrictTheDistributionToRobotsInside) {
  Aggregator a(unit_run());
  a.on_status(status(0, 1.0));
  a.on_status(status(1, 1.0));
  a.on_status(status(2, 1.0));
  wire::Poses p;
  p.tick = 5;
  p.robots.push_back({0, 0.1f, 0.2f, 0.0f, wire::Phase::inside, false});
  p.robots.push_back({1, 0.3f, 0.4f, 0.0f, wire::Phase::retreating, true});
  // robot 2 is not in D any more
  a.on_poses(p);
  EXPECT_EQ(a.estimates().count, 1u);

  // The kinetic world's poses carry no robots: they restrict nothing.
  wire::Poses empty;
  empty.tick = 6;
  a.on_poses(empty);
  EXPECT_EQ(a.estimates().count, 3u);
}

TEST(Aggregator, OlderPosesAndOlderStatusesOfTheSameAgentAreIgnoredAndCounted) {
  Aggregator a(unit_run());
  a.on_status(status(7, 1.0, 10.0, true, false, 300));
  a.on_status(status(7, 2.0, 9.0, true, false, 299));
  wire::Poses p;
  p.tick = 10;
  a.on_poses(p);
  p.tick = 9;
  a.on_poses(p);
  const auto s = a.snapshot();
  ASSERT_EQ(s.agents.size(), 1u);
  EXPECT_DOUBLE_EQ(s.agents[0].status.lambda_hat, 1.0);
  EXPECT_EQ(s.poses->tick, 10);
  EXPECT_EQ(s.samples.stale, 2u);
  EXPECT_EQ(s.samples.statuses, 2u);
  EXPECT_EQ(s.samples.poses, 2u);
  EXPECT_EQ(s.version, 2u);
}

TEST(Aggregator, EachPointCarriesTheEstimatesKnownWhenItWasTaken) {
  Aggregator a(unit_run());
  a.on_telemetry(telemetry_at(9.0, 4));
  a.on_status(status(0, 0.5));
  a.on_status(status(1, 1.5));
  a.on_telemetry(telemetry_at(10.0, 4));
  ASSERT_EQ(a.history().size(), 2u);
  EXPECT_EQ(a.history()[0].estimates, 0u);
  EXPECT_TRUE(std::isnan(a.history()[0].lambda_hat_mean));
  EXPECT_EQ(a.history()[1].estimates, 2u);
  EXPECT_DOUBLE_EQ(a.history()[1].lambda_hat_mean, 1.0);
  EXPECT_DOUBLE_EQ(a.history()[1].lambda_hat_min, 0.5);
  EXPECT_DOUBLE_EQ(a.history()[1].lambda_hat_max, 1.5);
}

TEST(Aggregator, HistoryKeepsEverySecondPointWhenFullAndDoublesItsSpacing) {
  AggregatorOptions o;
  o.history_capacity = 8;
  Aggregator a(unit_run(), o);
  for (int k = 0; k <= 20; ++k) a.on_telemetry(telemetry_at(0.1 * k, static_cast<std::uint32_t>(k)));
  // k = 0..8 fill 9 > 8 points: keep 0, 0.2, .., 0.8, spacing 0.2. Then every 0.2 s: 1.0 .. 1.6
  // make 9 again: keep 0, 0.4, .., 1.6, spacing 0.4. Then 2.0.
  const auto& h = a.history();
  ASSERT_EQ(h.size(), 6u);
  const std::uint32_t expected[] = {0, 4, 8, 12, 16, 20};
  for (std::size_t i = 0; i < h.size(); ++i) {
    EXPECT_EQ(h[i].inside, expected[i]) << i;
    EXPECT_NEAR(h[i].time, 0.4 * static_cast<double>(i), 1e-12) << i;
  }
  const auto s = a.snapshot();
  EXPECT_EQ(s.history_compactions, 2u);
  EXPECT_NEAR(s.history_spacing, 0.4, 1e-12);
  EXPECT_EQ(s.telemetry->inside, 20u);
  EXPECT_EQ(s.samples.telemetry, 21u);
}

TEST(Aggregator, AnInitialSpacingThinsTheSeriesFromTheStart) {
  AggregatorOptions o;
  o.history_spacing = 0.5;
  Aggregator a(unit_run(), o);
  for (int k = 0; k <= 20; ++k) a.on_telemetry(telemetry_at(0.1 * k, static_cast<std::uint32_t>(k)));
  ASSERT_EQ(a.history().size(), 5u);  // 0, 0.5, 1.0, 1.5, 2.0
  EXPECT_EQ(a.history().back().inside, 20u);
}

TEST(Aggregator, TheSameMomentAgainReplacesTheLastPoint) {
  Aggregator a(unit_run());
  a.on_telemetry(telemetry_at(1.0, 4));
  a.on_telemetry(telemetry_at(1.0, 3));
  ASSERT_EQ(a.history().size(), 1u);
  EXPECT_EQ(a.history()[0].inside, 3u);
}

TEST(Aggregator, AClockGoingBackStartsANewRun) {
  Aggregator a(unit_run());
  a.on_telemetry(telemetry_at(5.0, 4));
  a.on_status(status(0, 1.0, 5.0));
  wire::Poses p;
  p.tick = 100;
  a.on_poses(p);
  a.on_telemetry(telemetry_at(1.0, 2));
  const auto s = a.snapshot();
  EXPECT_EQ(s.runs, 2u);
  EXPECT_EQ(s.history_size, 1u);
  EXPECT_TRUE(s.agents.empty());
  EXPECT_FALSE(s.poses.has_value());
  EXPECT_EQ(s.telemetry->inside, 2u);
}

TEST(Aggregator, RefusesOptionsOutOfRange) {
  AggregatorOptions bins;
  bins.histogram_bins = 0;
  EXPECT_THROW(Aggregator(unit_run(), bins), std::invalid_argument);
  AggregatorOptions capacity;
  capacity.history_capacity = 3;
  EXPECT_THROW(Aggregator(unit_run(), capacity), std::invalid_argument);
  AggregatorOptions spacing;
  spacing.history_spacing = -1.0;
  EXPECT_THROW(Aggregator(unit_run(), spacing), std::invalid_argument);
  AggregatorOptions range;
  range.histogram_range_factor = 0.0;
  EXPECT_THROW(Aggregator(unit_run(), range), std::invalid_argument);
}

}  // namespace
}  // namespace retreat::telemetry
