// The HTTP layer in one process: scripted samples on the in-memory transport go through the
// bridge's Receiver into the LiveState; every endpoint answers on 127.0.0.1 with the expected
// numbers.

#include "retreat/bridge/server.hpp"

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "prometheus_check.hpp"
#include "retreat/bridge/receiver.hpp"
#include "retreat/transport/inmemory.hpp"

namespace retreat::bridge {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
namespace fs = std::filesystem;

telemetry::RunInfo run() {
  telemetry::RunInfo r;
  r.scenario = "server-test";
  r.area = 4.0;
  r.lambda_star = 1.0;
  r.half_x = 1.0;
  r.half_y = 1.0;
  return r;
}

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // One directory per test: ctest runs this file's tests in parallel processes.
    run_dir_ = ::testing::TempDir() + "/server_test_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::create_directories(run_dir_);
    std::ofstream(run_dir_ + "/telemetry.csv") << "tick,time,inside\n0,0,3\n";
    auto bus = transport::make_inmemory_bus();
    bridge_side_ = transport::make_inmemory_transport(bus, {0, "bridge", "", ""});
    publisher_ = transport::make_inmemory_transport(bus, {0, "arena", "", ""});
    receiver_ = std::make_unique<Receiver>(*bridge_side_, "retreat", state_);
    telemetry_.emplace(publisher_->create_writer<wire::ArenaTelemetry>(
        {wire::arena_telemetry_topic("retreat"), transport::QosIntent::state()}));
    statuses_.emplace(publisher_->create_writer<wire::AgentStatus>(
        {wire::agent_status_topic("retreat"), transport::QosIntent::state()}));
    poses_.emplace(publisher_->create_writer<wire::Poses>({wire::poses_topic("retreat"), transport::QosIntent::state()}));
  }
  void TearDown() override {
    if (server_) server_->stop();
    if (serving_.joinable()) serving_.join();
  }

  void start(ServerOptions options = {}) {
    options.run_dir = run_dir_;
    server_ = std::make_unique<Server>(state_, options);
    port_ = server_->bind({"127.0.0.1", 0});
    serving_ = std::thread([this] { server_->serve(); });
  }

  void publish(std::uint32_t inside, double time) {
    wire::ArenaTelemetry t;
    t.tick = static_cast<std::int64_t>(time * 100);
    t.time = time;
    t.inside = inside;
    t.waiting = 1;
    t.deliveries = 9;
    t.true_density = inside / 4.0;
    ASSERT_EQ(telemetry_->write(t), transport::WriteResult::ok);
    receiver_->poll();
  }

  httplib::Client client() {
    httplib::Client c("127.0.0.1", port_);
    c.set_connection_timeout(2);
    c.set_read_timeout(5);
    return c;
  }

  std::string run_dir_;
  LiveState state_{telemetry::Aggregator(run())};
  std::unique_ptr<transport::Transport> bridge_side_, publisher_;
  std::unique_ptr<Receiver> receiver_;
  std::optional<transport::Writer<wire::ArenaTelemetry>> telemetry_;
  std::optional<transport::Writer<wire::AgentStatus>> statuses_;
  std::optional<transport::Writer<wire::Poses>> poses_;
  std::unique_ptr<Server> server_;
  std::thread serving_;
  int port_ = 0;
};

TEST_F(ServerTest, StateHistoryAndMetricsCarryTheScriptedSamples) {
  wire::AgentStatus s;
  s.robot_id = 3;
  s.tick = 100;
  s.time = 1.0;
  s.deciding = true;
  s.lambda_hat = 1.1;
  statuses_->write(s);
  wire::Poses p;
  p.tick = 100;
  p.time = 1.0;
  p.robots.push_back({3, 0.5f, 0.25f, 0.0f, wire::Phase::inside, false});
  poses_->write(p);
  publish(4, 0.9);
  publish(5, 1.0);
  start();
  auto c = client();

  auto res = c.Get("/api/state");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/json");
  const auto j = json::parse(res->body);
  EXPECT_EQ(j["telemetry"]["inside"], 5);
  EXPECT_EQ(j["telemetry"]["waiting"], 1);
  EXPECT_EQ(j["agents"][0]["robot"], 3);
  EXPECT_DOUBLE_EQ(j["agents"][0]["lambda_hat"].get<double>(), 1.1);
  EXPECT_EQ(j["estimates"]["counts"][4], 1);  // 1.1 in [1.0, 1.25)
  EXPECT_DOUBLE_EQ(j["poses"]["robots"][0]["x"].get<double>(), 0.5);
  EXPECT_EQ(j["run"]["scenario"], "server-test");

  res = c.Get("/api/history");
  ASSERT_TRUE(res);
  const auto h = json::parse(res->body);
  EXPECT_EQ(h["inside"], json({4, 5}));
  EXPECT_EQ(h["time"], json({0.9, 1.0}));

  res = c.Get("/metrics");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  const auto m = testing::prometheus::parse(res->body);
  EXPECT_TRUE(m.errors.empty()) << testing::prometheus::describe(m);
  EXPECT_EQ(m.value("retreat_robots", {{"phase", "inside"}}), 5);
  EXPECT_EQ(m.value("retreat_agent_lambda_hat", {{"robot", "3"}}), 1.1);
  EXPECT_EQ(m.value("retreat_lambda_hat_count"), 1);
}

TEST_F(ServerTest, ServesThePageItsScriptsAndTheRunFilesOnly) {
  start();
  auto c = client();
  auto res = c.Get("/");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(res->body.find("<canvas id=\"arena\""), std::string::npos);
  for (const char* path : {"/app.js", "/style.css", "/vendor/uPlot.iife.min.js", "/vendor/uPlot.min.css", "/favicon.svg"}) {
    res = c.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_GT(res->body.size(), 100u) << path;
  }
  res = c.Get("/runs/telemetry.csv");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->body, "tick,time,inside\n0,0,3\n");
  EXPECT_EQ(res->get_header_value("Content-Disposition"), "attachment; filename=\"telemetry.csv\"");
  res = c.Get("/api/runs");
  ASSERT_TRUE(res);
  const auto runs = json::parse(res->body);
  ASSERT_EQ(runs["files"].size(), 1u);
  EXPECT_EQ(runs["files"][0]["name"], "telemetry.csv");
  for (const char* path : {"/runs/summary.json", "/runs/passwd", "/runs/..%2Ftelemetry.csv", "/runs/../x",
                           "/nothing", "/report.js"}) {
    res = c.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 404) << path;
  }
}

TEST_F(ServerTest, TheEventStreamSendsTheStateAndEachChange) {
  publish(2, 1.0);
  start();
  auto c = client();
  std::string received;
  int events = 0;
  const auto res = c.Get("/api/events", [&](const char* data, std::size_t n) {
    received.append(data, n);
    std::size_t at = 0;
    int complete = 0;
    while ((at = received.find("event: state\n", at)) != std::string::npos) {
      if (received.find("\n\n", at) == std::string::npos) break;
      ++complete;
      ++at;
    }
    if (complete > events) {
      events = complete;
      if (events == 1) publish(7, 2.0);  // a change: the next event carries it
    }
    return events < 2;
  });
  EXPECT_EQ(events, 2);
  EXPECT_EQ(received.rfind("retry: 1000\n\n", 0), 0u);
  const auto first = received.find("data: ");
  const auto second = received.find("data: ", first + 1);
  ASSERT_NE(second, std::string::npos);
  const auto a = json::parse(received.substr(first + 6, received.find('\n', first) - first - 6));
  const auto b = json::parse(received.substr(second + 6, received.find('\n', second) - second - 6));
  EXPECT_EQ(a["telemetry"]["inside"], 2);
  EXPECT_EQ(b["telemetry"]["inside"], 7);
}

TEST_F(ServerTest, EventStreamsBeyondTheLimitGet503AndTheServerStillAnswers) {
  ServerOptions o;
  o.max_event_streams = 1;
  start(o);
  std::atomic<bool> streaming{false};
  std::thread first([&] {
    auto c = client();
    c.Get("/api/events", [&](const char*, std::size_t) {
      streaming.store(true);
      return true;  // until the server stops
    });
  });
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!streaming.load() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  ASSERT_TRUE(streaming.load());
  auto c = client();
  auto res = c.Get("/api/events");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 503);
  res = c.Get("/api/state");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(server_->event_streams(), 1u);
  server_->stop();
  first.join();
  // The stream's slot is given back when httplib's worker finishes the response, which can be
  // just after the client has read its end; serve() returns only once every worker has.
  serving_.join();
  EXPECT_EQ(server_->event_streams(), 0u);
}

TEST_F(ServerTest, ABodyOverTheLimitGets413) {
  ServerOptions o;
  o.max_payload = 1024;
  start(o);
  auto c = client();
  const auto res = c.Post("/api/state", std::string(4096, 'x'), "text/plain");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 413);
  EXPECT_EQ(c.Get("/api/state")->status, 200);
}

TEST_F(ServerTest, BindingAPortInUseFailsWithOneLine) {
  start();
  Server second(state_, {});
  try {
    second.bind({"127.0.0.1", port_});
    FAIL() << "bound a port in use";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("127.0.0.1:" + std::to_string(port_)), std::string::npos) << message;
    EXPECT_NE(message.find("Address already in use"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace retreat::bridge
