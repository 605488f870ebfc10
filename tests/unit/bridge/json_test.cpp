// JSON of the API: the state and the history carry the aggregator's numbers; no estimate is
// null, never NaN.

#include "retreat/bridge/json.hpp"

#include <gtest/gtest.h>

namespace retreat::bridge {
namespace {

telemetry::Aggregator scripted() {
  telemetry::RunInfo run;
  run.scenario = "json";
  run.shape = "rectangle";
  run.half_x = 1.5;
  run.half_y = 1.0;
  run.area = 6.0;
  run.lambda_star = 0.5;
  telemetry::Aggregator a(run);
  wire::AgentStatus s;
  s.robot_id = 2;
  s.tick = 30;
  s.time = 0.9;
  s.deciding = true;
  s.lambda_hat = 0.4;
  s.epsilon = 0.02;
  s.onsets_in_window = 3;
  a.on_status(s);
  wire::Poses p;
  p.tick = 30;
  p.time = 0.9;
  p.robots.push_back({2, 0.5f, -0.25f, 1.5f, wire::Phase::inside, true});
  p.pickups.push_back({0.25f, 0.75f});
  p.dropoffs.push_back({-0.5f, 0.5f});
  a.on_poses(p);
  for (int k = 0; k < 3; ++k) {
    wire::ArenaTelemetry t;
    t.tick = 10 * k;
    t.time = 0.3 * k;
    t.inside = static_cast<std::uint32_t>(3 + k);
    t.deliveries = static_cast<std::uint64_t>(k);
    t.true_density = (3.0 + k) / 6.0;
    a.on_telemetry(t);
  }
  return a;
}

TEST(StateJson, CarriesTheRunTheTelemetryThePosesAndTheAgents) {
  const auto a = scripted();
  const auto j = state_json(a.snapshot());
  EXPECT_EQ(j["run"]["scenario"], "json");
  EXPECT_EQ(j["run"]["shape"], "rectangle");
  EXPECT_EQ(j["run"]["half_extent"], nlohmann::json({1.5, 1.0}));
  EXPECT_DOUBLE_EQ(j["run"]["optimal_population"].get<double>(), 3.0);
  EXPECT_EQ(j["telemetry"]["inside"], 5);
  EXPECT_EQ(j["telemetry"]["tick"], 20);
  EXPECT_EQ(j["poses"]["robots"].size(), 1u);
  EXPECT_EQ(j["poses"]["robots"][0]["phase"], "inside");
  EXPECT_EQ(j["poses"]["robots"][0]["loaded"], true);
  EXPECT_DOUBLE_EQ(j["poses"]["robots"][0]["x"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["poses"]["pickups"][0][1].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(j["poses"]["dropoffs"][0][0].get<double>(), -0.5);
  ASSERT_EQ(j["agents"].size(), 1u);
  EXPECT_EQ(j["agents"][0]["robot"], 2);
  EXPECT_EQ(j["agents"][0]["counted"], true);
  EXPECT_DOUBLE_EQ(j["agents"][0]["lambda_hat"].get<double>(), 0.4);
  // λ* = 0.5: bins of 0.125; 0.4 falls in bin 3.
  EXPECT_DOUBLE_EQ(j["estimates"]["bin_width"].get<double>(), 0.125);
  EXPECT_EQ(j["estimates"]["counts"][3], 1);
  EXPECT_EQ(j["estimates"]["count"], 1);
  EXPECT_EQ(j["history"]["points"], 3);
  EXPECT_EQ(j["history"]["last"]["inside"], 5);
  EXPECT_EQ(j["samples"]["arena_telemetry"], 3);
  EXPECT_EQ(j["runs"], 1);
  EXPECT_EQ(j["version"], 5);
}

TEST(StateJson, WithoutSamplesHasNullTelemetryPosesAndEstimates) {
  telemetry::RunInfo run;
  run.lambda_star = 1.0;
  const auto j = state_json(telemetry::Aggregator(run).snapshot());
  EXPECT_TRUE(j["telemetry"].is_null());
  EXPECT_TRUE(j["poses"].is_null());
  EXPECT_TRUE(j["estimates"]["mean"].is_null());
  EXPECT_TRUE(j["history"]["last"].is_null());
  // Parses back: no NaN in the text.
  EXPECT_TRUE(nlohmann::json::parse(j.dump()).is_object());
}

TEST(HistoryJson, HasOneArrayPerFieldOldestFirst) {
  const auto a = scripted();
  const auto s = a.snapshot();
  const auto j = history_json(a.history(), s.history_spacing, s.history_compactions);
  EXPECT_EQ(j["points"], 3);
  EXPECT_EQ(j["time"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["time"][2].get<double>(), 0.6);
  EXPECT_EQ(j["inside"], nlohmann::json({3, 4, 5}));
  EXPECT_EQ(j["deliveries"], nlohmann::json({0, 1, 2}));
  // The status arrived before the first telemetry: every point has one estimate.
  EXPECT_EQ(j["estimates"], nlohmann::json({1, 1, 1}));
  EXPECT_DOUBLE_EQ(j["lambda_hat_mean"][0].get<double>(), 0.4);
  for (const char* key : {"tick", "waiting", "retreating", "departed", "lost_agents", "true_density",
                          "ticks_per_second", "lambda_hat_min", "lambda_hat_max"}) {
    EXPECT_EQ(j[key].size(), 3u) << key;
  }
}

}  // namespace
}  // namespace retreat::bridge
