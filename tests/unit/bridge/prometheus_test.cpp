// Prometheus text rendering: the writer's escaping and formatting, the swarm's metrics with
// exact values, and the whole text through an independent line-format checker.

#include "retreat/telemetry/prometheus.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "prometheus_check.hpp"

namespace retreat::telemetry {
namespace {

namespace prom = retreat::testing::prometheus;

TEST(PrometheusWriter, FormatsValuesAsTheShortestRoundTripDecimal) {
  EXPECT_EQ(PrometheusWriter::format_value(1.5), "1.5");
  EXPECT_EQ(PrometheusWriter::format_value(0.1), "0.1");
  EXPECT_EQ(PrometheusWriter::format_value(3.0), "3");
  EXPECT_EQ(PrometheusWriter::format_value(-2.25), "-2.25");
  EXPECT_EQ(PrometheusWriter::format_value(1e21), "1e+21");
  EXPECT_EQ(PrometheusWriter::format_value(std::nan("")), "NaN");
  EXPECT_EQ(PrometheusWriter::format_value(HUGE_VAL), "+Inf");
  EXPECT_EQ(PrometheusWriter::format_value(-HUGE_VAL), "-Inf");
}

TEST(PrometheusWriter, EscapesBackslashQuoteAndNewlineInLabelValues) {
  EXPECT_EQ(PrometheusWriter::escape_label_value("a\"b\\c\nd"), "a\\\"b\\\\c\\nd");
  PrometheusWriter w;
  w.family("x_total", "counter", "A help with a \\ and a\nnewline.");
  w.sample(1, {{"who", "a\"b\\c\nd"}});
  const auto p = prom::parse(w.text());
  EXPECT_TRUE(p.errors.empty()) << prom::describe(p) << w.text();
  EXPECT_EQ(p.value("x_total", {{"who", "a\"b\\c\nd"}}), 1.0);
}

TEST(PrometheusWriter, RefusesBadNamesRepeatedFamiliesAndSamplesWithoutAFamily) {
  PrometheusWriter w;
  EXPECT_THROW(w.sample(1.0), std::logic_error);
  EXPECT_THROW(w.family("9lives", "gauge", "x"), std::invalid_argument);
  EXPECT_THROW(w.family("ok", "gaugeish", "x"), std::invalid_argument);
  w.family("ok", "gauge", "x");
  EXPECT_THROW(w.family("ok", "gauge", "x"), std::invalid_argument);
  EXPECT_THROW(w.sample(1.0, {{"bad-label", "v"}}), std::invalid_argument);
}

TEST(PrometheusWriter, WritesCumulativeHistogramBuckets) {
  PrometheusWriter w;
  w.family("h", "histogram", "A histogram.");
  w.histogram({1.0, 2.0, 3.0}, {2, 0, 5}, 1, 12.5);
  EXPECT_EQ(w.text(),
            "# HELP h A histogram.\n# TYPE h histogram\n"
            "h_bucket{le=\"1\"} 2\nh_bucket{le=\"2\"} 2\nh_bucket{le=\"3\"} 7\nh_bucket{le=\"+Inf\"} 8\n"
            "h_sum 12.5\nh_count 8\n");
  EXPECT_TRUE(prom::parse(w.text()).errors.empty());
}

Snapshot scripted_snapshot() {
  RunInfo run;
  run.area = 4.0;
  run.lambda_star = 1.0;
  Aggregator a(run);
  wire::ArenaTelemetry t;
  t.tick = 3000;
  t.time = 90.0;
  t.inside = 5;
  t.waiting = 2;
  t.retreating = 1;
  t.departed = 4;
  t.lost_agents = 1;
  t.true_density = 1.25;
  t.deliveries = 17;
  t.ticks_per_second = 2500.5;
  wire::AgentStatus s;
  s.tick = 3000;
  s.time = 90.0;
  s.deciding = true;
  for (wire::RobotId id : {3u, 1u, 2u, 4u}) {
    s.robot_id = id;
    s.lambda_hat = 0.5 * id;  // 1.5, 0.5, 1.0, 2.0
    s.epsilon = 0.01 * id;
    s.onsets_in_window = id;
    a.on_status(s);
  }
  a.on_telemetry(t);
  wire::Poses p;
  p.tick = 3000;
  for (wire::RobotId id : {1u, 2u, 3u, 4u}) p.robots.push_back({id, 0, 0, 0, wire::Phase::inside, id % 2 == 0});
  a.on_poses(p);
  return a.snapshot();
}

TEST(SwarmMetrics, ParseAsPrometheusTextWithTheExpectedNumbers) {
  PrometheusWriter w;
  write_swarm_metrics(w, scripted_snapshot());
  const auto p = prom::parse(w.text());
  ASSERT_TRUE(p.errors.empty()) << prom::describe(p) << w.text();
  EXPECT_EQ(p.value("retreat_robots", {{"phase", "inside"}}), 5);
  EXPECT_EQ(p.value("retreat_robots", {{"phase", "waiting"}}), 2);
  EXPECT_EQ(p.value("retreat_robots", {{"phase", "retreating"}}), 1);
  EXPECT_EQ(p.value("retreat_robots", {{"phase", "departed"}}), 4);
  EXPECT_EQ(p.value("retreat_lost_agents"), 1);
  EXPECT_EQ(p.value("retreat_deliveries_total"), 17);
  EXPECT_EQ(p.value("retreat_arena_tick"), 3000);
  EXPECT_EQ(p.value("retreat_arena_time_seconds"), 90);
  EXPECT_EQ(p.value("retreat_arena_ticks_per_second"), 2500.5);
  EXPECT_EQ(p.value("retreat_true_density"), 1.25);
  EXPECT_EQ(p.value("retreat_optimal_population"), 4);
  EXPECT_EQ(p.value("retreat_optimal_density"), 1);
  EXPECT_EQ(p.value("retreat_robots_loaded"), 2);
  EXPECT_EQ(p.value("retreat_agents_reporting"), 4);
  EXPECT_EQ(p.value("retreat_agent_lambda_hat", {{"robot", "3"}}), 1.5);
  EXPECT_EQ(p.value("retreat_agent_epsilon", {{"robot", "2"}}), 0.02);
  EXPECT_EQ(p.value("retreat_agent_onsets_in_window", {{"robot", "4"}}), 4);
  EXPECT_EQ(p.value("retreat_agent_deciding", {{"robot", "1"}}), 1);
  // Bins of 0.25 over [0, 3): 0.5 -> bin 2 (le 0.75), 1.0 -> bin 4 (le 1.25), 1.5 -> bin 6
  // (le 1.75), 2.0 -> bin 8 (le 2.25).
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "0.5"}}), 0);
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "0.75"}}), 1);
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "1.25"}}), 2);
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "1.75"}}), 3);
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "2.25"}}), 4);
  EXPECT_EQ(p.value("retreat_lambda_hat_bucket", {{"le", "+Inf"}}), 4);
  EXPECT_EQ(p.value("retreat_lambda_hat_count"), 4);
  EXPECT_EQ(p.value("retreat_lambda_hat_sum"), 5);
  EXPECT_EQ(p.value("retreat_bridge_samples_total", {{"topic", "agent_status"}}), 4);
  EXPECT_EQ(p.types.at("retreat_deliveries_total"), "counter");
  EXPECT_EQ(p.types.at("retreat_lambda_hat"), "histogram");
}

TEST(SwarmMetrics, BeforeAnyTelemetryOnlyTheRunsConstantsAndAnEmptyHistogramAppear) {
  RunInfo run;
  run.area = 2.0;
  run.lambda_star = 1.5;
  PrometheusWriter w;
  write_swarm_metrics(w, Aggregator(run).snapshot());
  const auto p = prom::parse(w.text());
  ASSERT_TRUE(p.errors.empty()) << prom::describe(p);
  EXPECT_FALSE(p.has("retreat_robots"));
  EXPECT_EQ(p.value("retreat_optimal_population"), 3);
  EXPECT_EQ(p.value("retreat_lambda_hat_count"), 0);
}

TEST(PrometheusCheck, RejectsTextThatBreaksTheFormat) {
  // The checker is not vacuous: each of these is invalid for one reason.
  const char* bad[] = {
      "a 1",                                                         // no final newline
      "a{x=\"1\\t\"} 1\n",                                          // bad escape
      "a{x=\"1\"\n",                                                 // unclosed label set
      "a one\n",                                                     // bad value
      "1a 1\n",                                                      // bad name
      "a 1\nb 2\na{x=\"2\"} 3\n",                                    // a not contiguous
      "a 1\na 2\n",                                                  // series repeated
      "# TYPE a gauge\n# TYPE a gauge\na 1\n",                       // TYPE twice
      "a 1\n# TYPE a gauge\n",                                       // TYPE after samples
      "# TYPE h histogram\nh_bucket{le=\"1\"} 2\nh_bucket{le=\"+Inf\"} 1\nh_sum 1\nh_count 1\n",  // decreasing
      "# TYPE h histogram\nh_bucket{le=\"1\"} 2\nh_sum 1\nh_count 2\n",                           // no +Inf
      "# TYPE h histogram\nh_bucket{le=\"+Inf\"} 2\nh_sum 1\nh_count 3\n",                        // count differs
  };
  for (const char* text : bad) EXPECT_FALSE(prom::parse(text).errors.empty()) << text;
  EXPECT_TRUE(prom::parse("# a comment\n\na{b=\"c\",} 1 1700000000000\n").errors.empty());
}

}  // namespace
}  // namespace retreat::telemetry
