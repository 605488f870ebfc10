// retreat-bridge as a program, fed by a scripted DDS participant (no arena): every endpoint is
// well-formed with the expected numbers, /metrics parses as Prometheus text, the event stream
// follows a change, the run files download, the bridge matches only the three observation
// topics, and SIGTERM ends it with exit code 0 and a report. DDS domain 98.

#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>

#include <filesystem>
#include <fstream>

#include "bridge_support.hpp"
#include "prometheus_check.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/testing/domains.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
using testing::eventually;
namespace fs = std::filesystem;
namespace tb = testing::bridge;

constexpr int api_domain = testing::domains::bridge.at(0);

std::string vendor() {
  const auto v = transport::dds_vendors();
  return std::find(v.begin(), v.end(), "fastdds") != v.end() ? "fastdds" : v.front();
}

const std::string scenario_yaml =
    "name: bridge-api\nseed: 3\n"
    "arena: {encounter_model: kinetic, shape: rectangle, width: 2.0, height: 2.0, robots_inside: 4, "
    "robots_waiting: 2}\n";

wire::ArenaTelemetry telemetry(std::int64_t tick, std::uint32_t inside) {
  wire::ArenaTelemetry t;
  t.tick = tick;
  t.time = 0.03 * static_cast<double>(tick);
  t.inside = inside;
  t.waiting = 2;
  t.retreating = 1;
  t.departed = 3;
  t.lost_agents = 1;
  t.true_density = inside / 4.0;
  t.deliveries = 42;
  t.ticks_per_second = 1234.5;
  return t;
}

TEST(BridgeApi, EveryEndpointServesTheScriptedSwarm) {
  if (transport::dds_vendors().empty()) GTEST_SKIP() << "no DDS vendor built";
  const std::string dir = ::testing::TempDir() + "/bridge_api";
  fs::remove_all(dir);
  fs::create_directories(dir + "/run");
  const std::string scenario = dir + "/scenario.yaml";
  std::ofstream(scenario) << scenario_yaml;
  // A run directory as the arena leaves it, for the downloads and the report.
  fs::copy_file(scenario, dir + "/run/scenario.yaml");
  {
    std::ofstream csv(dir + "/run/telemetry.csv");
    csv << "tick,time,inside,waiting,retreating,departed,true_density,deliveries,onsets,free,loaded,"
           "free_colliding,loaded_colliding\n";
    for (int k = 0; k < 50; ++k) csv << k << ',' << 0.03 * k << ",3,2,1,3,0.75,42,0,3,0,0,0\n";
  }

  // The scripted source: telemetry, poses and statuses on a participant of our own, plus a
  // writer on each of a robot's own topics, which the bridge must never match.
  const auto v = vendor();
  auto source = transport::make_transport(v, {api_domain, "bridge-api-source", "", ""});
  const auto prefix = std::string("retreat");
  auto t_writer = source->create_writer<wire::ArenaTelemetry>({wire::arena_telemetry_topic(prefix), transport::QosIntent::state()});
  auto p_writer = source->create_writer<wire::Poses>({wire::poses_topic(prefix), transport::QosIntent::state()});
  auto s_writer = source->create_writer<wire::AgentStatus>({wire::agent_status_topic(prefix), transport::QosIntent::state()});
  auto proximity = source->create_writer<wire::ProximityFrame>({wire::proximity_topic(prefix, 0), transport::QosIntent::control()});
  auto decision = source->create_writer<wire::Decision>({wire::decision_topic(prefix, 0), transport::QosIntent::control()});
  wire::Poses poses;
  poses.tick = 100;
  poses.time = 3.0;
  poses.robots = {{0, 0.5f, 0.5f, 0.0f, wire::Phase::inside, false},
                  {1, -0.5f, 0.25f, 1.0f, wire::Phase::inside, true},
                  {2, 0.0f, -0.5f, 2.0f, wire::Phase::inside, false},
                  {5, 0.9f, 0.9f, 3.0f, wire::Phase::retreating, false}};
  poses.pickups = {{0.25f, 0.25f}};
  poses.dropoffs = {{-0.25f, -0.25f}};
  ASSERT_EQ(p_writer.write(poses), transport::WriteResult::ok);
  // λ* of the default model is 1.5076: bins of 3λ*/12 = 0.3769 robots/m².
  for (wire::RobotId id : {0u, 1u, 2u}) {
    wire::AgentStatus s;
    s.robot_id = id;
    s.tick = 100;
    s.time = 3.0;
    s.deciding = true;
    s.lambda_hat = 0.5 + id;  // 0.5 (bin 1), 1.5 (bin 3), 2.5 (bin 6)
    s.epsilon = 0.001 * id;
    s.onsets_in_window = 2 * id;
    ASSERT_EQ(s_writer.write(s), transport::WriteResult::ok);
  }
  ASSERT_EQ(t_writer.write(telemetry(90, 3)), transport::WriteResult::ok);
  ASSERT_EQ(t_writer.write(telemetry(100, 3)), transport::WriteResult::ok);

  auto b = tb::start_bridge({"--scenario", scenario, "--dds", v, "--domain", std::to_string(api_domain), "--http",
                             "127.0.0.1:0", "--out", dir + "/run"},
                            dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  EXPECT_EQ(b.url, "http://127.0.0.1:" + std::to_string(b.port) + "/");

  // Transient-local: the newest telemetry, poses and statuses arrive without being re-sent.
  json state;
  ASSERT_TRUE(eventually(
      [&] {
        const auto r = tb::get(b.port, "/api/state");
        if (!r || r->status != 200) return false;
        state = json::parse(r->body);
        return !state["telemetry"].is_null() && !state["poses"].is_null() && state["agents"].size() == 3;
      },
      retreat::testing::hang_ceiling))
      << state.dump();
  EXPECT_EQ(state["run"]["scenario"], "bridge-api");
  EXPECT_EQ(state["run"]["shape"], "rectangle");
  EXPECT_DOUBLE_EQ(state["run"]["area"].get<double>(), 4.0);
  EXPECT_NEAR(state["run"]["lambda_star"].get<double>(), 1.5076, 1e-4);
  EXPECT_EQ(state["telemetry"]["tick"], 100);
  EXPECT_EQ(state["telemetry"]["inside"], 3);
  EXPECT_EQ(state["telemetry"]["waiting"], 2);
  EXPECT_EQ(state["telemetry"]["lost_agents"], 1);
  EXPECT_EQ(state["telemetry"]["deliveries"], 42);
  EXPECT_DOUBLE_EQ(state["telemetry"]["ticks_per_second"].get<double>(), 1234.5);
  EXPECT_EQ(state["poses"]["robots"].size(), 4u);
  EXPECT_EQ(state["poses"]["robots"][3]["phase"], "retreating");
  EXPECT_EQ(state["poses"]["pickups"].size(), 1u);
  const auto& est = state["estimates"];
  EXPECT_EQ(est["count"], 3);
  EXPECT_EQ(est["counts"][1], 1);
  EXPECT_EQ(est["counts"][3], 1);
  EXPECT_EQ(est["counts"][6], 1);
  EXPECT_DOUBLE_EQ(est["mean"].get<double>(), 1.5);

  auto r = tb::get(b.port, "/api/history");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  const auto history = json::parse(r->body);
  ASSERT_GE(history["time"].size(), 1u);
  EXPECT_EQ(history["inside"].back(), 3);
  EXPECT_EQ(history["time"].size(), history["inside"].size());

  // The matched-writer gauges are refreshed every 200 ms by the receiving thread.
  testing::prometheus::Parsed m;
  ASSERT_TRUE(eventually(
      [&] {
        r = tb::get(b.port, "/metrics");
        if (!r) return false;
        m = testing::prometheus::parse(r->body);
        return m.value("retreat_bridge_writers_matched", {{"topic", "poses"}}) == 1;
      },
      retreat::testing::hang_ceiling));
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->content_type, "text/plain; version=0.0.4; charset=utf-8");
  EXPECT_TRUE(m.errors.empty()) << testing::prometheus::describe(m) << r->body;
  EXPECT_EQ(m.value("retreat_robots", {{"phase", "inside"}}), 3);
  EXPECT_EQ(m.value("retreat_deliveries_total"), 42);
  EXPECT_EQ(m.value("retreat_agent_lambda_hat", {{"robot", "2"}}), 2.5);
  EXPECT_EQ(m.value("retreat_lambda_hat_count"), 3);
  EXPECT_EQ(m.value("retreat_robots_loaded"), 1);
  EXPECT_EQ(m.value("retreat_bridge_writers_matched", {{"topic", "agent_status"}}), 1);
  EXPECT_GE(m.value("retreat_bridge_http_responses_total", {{"code", "2xx"}}), 1);
  EXPECT_EQ(m.value("retreat_bridge_event_streams"), 0);

  r = tb::get(b.port, "/");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("app.js"), std::string::npos);
  r = tb::get(b.port, "/runs/telemetry.csv");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->body.rfind("tick,time,inside", 0), 0u);
  r = tb::get(b.port, "/runs/scenario.yaml");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  r = tb::get(b.port, "/api/runs");
  ASSERT_TRUE(r);
  EXPECT_EQ(json::parse(r->body)["recording"], true);
  r = tb::get(b.port, "/report");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("window.REPORT"), std::string::npos);

  // The event stream: the current state first, then the next change.
  {
    httplib::Client c("127.0.0.1", b.port);
    c.set_read_timeout(10);
    std::string received;
    bool changed = false;
    bool published = false;
    c.Get("/api/events", [&](const char* data, std::size_t n) {
      received.append(data, n);
      if (!published && received.find("\"inside\":3") != std::string::npos) {
        published = true;
        t_writer.write(telemetry(200, 4));
      }
      changed = received.find("\"inside\":4") != std::string::npos;
      return !changed;
    });
    EXPECT_TRUE(published) << received.substr(0, 300);
    EXPECT_TRUE(changed) << received.substr(0, 300);
    EXPECT_NE(received.find("event: state\n"), std::string::npos);
  }

  // Only the three observation topics: the robot's own writers stayed unmatched.
  EXPECT_EQ(proximity.matched_count(), 0u);
  EXPECT_EQ(decision.matched_count(), 0u);
  EXPECT_EQ(t_writer.matched_count(), 1u);
  EXPECT_EQ(s_writer.matched_count(), 1u);

  // SIGTERM: exit 0, agent statuses recorded, and a report in the run directory.
  EXPECT_EQ(b.process->stop(retreat::testing::hang_ceiling), 0) << testing::read_file(b.log);
  EXPECT_TRUE(fs::exists(dir + "/run/report.html")) << testing::read_file(b.log);
  const auto statuses = testing::read_file(dir + "/run/agent_status.csv");
  EXPECT_EQ(std::count(statuses.begin(), statuses.end(), '\n'), 1 + 3) << statuses;
}

}  // namespace
}  // namespace retreat
