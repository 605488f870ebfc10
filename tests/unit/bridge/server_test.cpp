// The HTTP layer in one process: scripted samples on the in-memory transport go through the
// bridge's Receiver into the LiveState; every endpoint answers on 127.0.0.1 with the expected
// numbers.

#include "retreat/bridge/server.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "prometheus_check.hpp"
#include "retreat/bridge/receiver.hpp"
#include "retreat/testing/process.hpp"
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
  // The stream's slot is given back when its session ends, which can be just after the client
  // has read its end; serve() returns only once every session has.
  serving_.join();
  EXPECT_EQ(server_->event_streams(), 0u);
}

/// A TCP connection to 127.0.0.1:port: the socket, or -1.
int connect_local(int port) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(static_cast<std::uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &sa.sin_addr);
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd >= 0 && ::connect(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

/// Event streams on raw sockets, read together: each one's `id:` lines (the state's versions).
class Viewers {
 public:
  Viewers(int port, std::size_t count) {
    const std::string request = "GET /api/events HTTP/1.1\r\nHost: x\r\n\r\n";
    for (std::size_t i = 0; i < count; ++i) {
      const int fd = connect_local(port);
      if (fd < 0 || ::send(fd, request.data(), request.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(request.size())) {
        if (fd >= 0) ::close(fd);
        continue;
      }
      fds_.push_back(fd);
    }
    text_.resize(fds_.size());
    ids_.resize(fds_.size());
    parsed_.resize(fds_.size(), 0);
  }
  ~Viewers() {
    for (int fd : fds_) ::close(fd);
  }
  Viewers(const Viewers&) = delete;
  Viewers& operator=(const Viewers&) = delete;

  std::size_t open() const { return fds_.size(); }
  /// Reads whatever has arrived, waiting up to @p wait for the first bytes.
  void read(std::chrono::milliseconds wait) {
    std::vector<pollfd> polled;
    for (int fd : fds_) polled.push_back({fd, POLLIN, 0});
    if (::poll(polled.data(), polled.size(), static_cast<int>(wait.count())) <= 0) return;
    char buffer[65536];
    for (std::size_t i = 0; i < polled.size(); ++i) {
      if ((polled[i].revents & (POLLIN | POLLHUP)) == 0) continue;
      const auto n = ::recv(fds_[i], buffer, sizeof buffer, MSG_DONTWAIT);
      if (n > 0) text_[i].append(buffer, static_cast<std::size_t>(n));
      // Complete events only: "id: N" up to the blank line that ends the event.
      for (;;) {
        const auto at = text_[i].find("\nid: ", parsed_[i]);
        if (at == std::string::npos) break;
        const auto end = text_[i].find("\n\n", at);
        if (end == std::string::npos) break;
        ids_[i].push_back(std::stoull(text_[i].substr(at + 5)));
        parsed_[i] = end;
      }
    }
  }
  /// Reads until every viewer's last event has version @p v (false after the hang ceiling).
  bool reach(std::uint64_t v) {
    return testing::eventually(
        [&] {
          read(20ms);
          return all_at(v);
        },
        testing::hang_ceiling);
  }
  /// Whether every viewer's last event has version @p v.
  bool all_at(std::uint64_t v) const {
    for (const auto& ids : ids_) {
      if (ids.empty() || ids.back() != v) return false;
    }
    return true;
  }
  const std::vector<std::vector<std::uint64_t>>& ids() const { return ids_; }

 private:
  std::vector<int> fds_;
  std::vector<std::string> text_;
  std::vector<std::vector<std::uint64_t>> ids_;
  std::vector<std::size_t> parsed_;
};

TEST_F(ServerTest, TwoHundredEventStreamsGetEveryUpdateInOrder) {
  publish(1, 1.0);
  start();
  Viewers viewers(port_, 200);
  ASSERT_EQ(viewers.open(), 200u);
  // The state at connection, then each update once every viewer has the one before: every
  // viewer gets every version, in order.
  std::vector<std::uint64_t> published = {state_.version()};
  ASSERT_TRUE(viewers.reach(published.back()));
  EXPECT_EQ(server_->event_streams(), 200u);
  for (int k = 2; k <= 6; ++k) {
    publish(static_cast<std::uint32_t>(k), k);
    published.push_back(state_.version());
    ASSERT_TRUE(viewers.reach(published.back())) << "update " << k;
  }
  for (const auto& ids : viewers.ids()) ASSERT_EQ(ids, published);
  // Updates faster than events are sent: a viewer may skip states in between, but it never
  // goes back and it ends at the newest.
  for (int k = 7; k <= 30; ++k) publish(static_cast<std::uint32_t>(k), k);
  ASSERT_TRUE(viewers.reach(state_.version()));
  for (const auto& ids : viewers.ids()) {
    EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()) && std::adjacent_find(ids.begin(), ids.end()) == ids.end());
  }
  const auto r = server_->responses();
  EXPECT_EQ(r[2], 200u);  // one 200 per stream, nothing else
  EXPECT_EQ(r[5], 0u);
}

TEST_F(ServerTest, HeadRangesMethodsAndABusyReportQueue) {
  ServerOptions o;
  o.max_queued = 0;  // no report may wait: /report is always busy
  start(o);
  auto c = client();
  const auto whole = c.Get("/app.js");
  ASSERT_TRUE(whole);
  ASSERT_EQ(whole->status, 200);
  EXPECT_EQ(whole->get_header_value("Accept-Ranges"), "bytes");
  // HEAD: GET's headers, no body.
  auto res = c.Head("/app.js");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Length"), std::to_string(whole->body.size()));
  EXPECT_TRUE(res->body.empty());
  res = c.Head("/runs/telemetry.csv");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Content-Length"), std::to_string(std::string("tick,time,inside\n0,0,3\n").size()));
  // Ranges: a part, the last bytes, one past the end.
  res = c.Get("/app.js", {{"Range", "bytes=10-19"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 206);
  EXPECT_EQ(res->body, whole->body.substr(10, 10));
  EXPECT_EQ(res->get_header_value("Content-Range"), "bytes 10-19/" + std::to_string(whole->body.size()));
  res = c.Get("/app.js", {{"Range", "bytes=-5"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 206);
  EXPECT_EQ(res->body, whole->body.substr(whole->body.size() - 5));
  res = c.Get("/app.js", {{"Range", "bytes=" + std::to_string(whole->body.size()) + "-"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 416);
  EXPECT_EQ(res->get_header_value("Content-Range"), "bytes */" + std::to_string(whole->body.size()));
  // A method a path does not take: 405 naming the ones it does.
  res = c.Post("/api/state", "x", "text/plain");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 405);
  EXPECT_EQ(res->get_header_value("Allow"), "GET, HEAD");
  res = c.Get("/api/replay?play=%zz");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);  // a broken escape
  // A report while the queue is full: 503 with a time to come back.
  res = c.Get("/report");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 503);
  EXPECT_EQ(res->get_header_value("Retry-After"), "2");
  EXPECT_EQ(c.Get("/api/state")->status, 200);
}

TEST_F(ServerTest, AReportIsRenderedOnAWorker) {
  start();
  auto c = client();
  // The run directory has no summary yet: the worker's answer is the report's refusal.
  const auto res = c.Get("/report");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 409);
  EXPECT_EQ(res->body.rfind("409 no report yet: ", 0), 0u) << res->body;
}

TEST_F(ServerTest, AStreamGetsANewAggregatorsStateEvenWhenItsCountIsBack) {
  publish(2, 1.0);
  publish(3, 2.0);
  start();
  Viewers viewer(port_, 1);
  ASSERT_EQ(viewer.open(), 1u);
  ASSERT_TRUE(viewer.reach(state_.version()));
  const auto before = state_.version();
  // What a replay seeking back does: a new aggregator, brought to the same count of samples as
  // the old one had, with another state.
  state_.update([](telemetry::Aggregator& a) {
    const auto count = a.version();
    a = telemetry::Aggregator(run());
    wire::ArenaTelemetry t;
    t.inside = 9;
    while (a.version() < count) {
      t.time += 0.5;
      t.tick += 1;
      a.on_telemetry(t);
    }
  });
  EXPECT_GT(state_.version(), before);
  ASSERT_TRUE(viewer.reach(state_.version()));
  const auto r = client().Get("/api/state");
  ASSERT_TRUE(r);
  EXPECT_EQ(json::parse(r->body)["telemetry"]["inside"], 9);
}

/// A connection to 127.0.0.1 that sent @p bytes (and stays open).
class RawConnection {
 public:
  RawConnection(int port, const std::string& bytes) : fd_(connect_local(port)) {
    if (fd_ >= 0) send(bytes);
  }
  ~RawConnection() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  void send(const std::string& bytes) { ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }
  /// What arrives until the server closes (or the hang ceiling).
  std::string read_to_close() {
    std::string all;
    char buffer[4096];
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(std::chrono::milliseconds(testing::hang_ceiling).count())) <= 0) return all;
      const auto n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) return all;
      all.append(buffer, static_cast<std::size_t>(n));
    }
  }

 private:
  int fd_ = -1;
};

TEST_F(ServerTest, AnAddressAtItsCapEvictsItsOldestWaitingConnectionOrIsRefused) {
  ServerOptions o;
  o.max_connections_per_address = 3;
  o.read_timeout = std::chrono::minutes(10);  // nothing here is dropped for being slow
  start(o);
  const std::string unfinished = "GET /api/state HTTP/1.1\r\nX-Slow: ";
  const std::string rest = "a\r\nConnection: close\r\n\r\n";
  const auto connections_are = [&](std::size_t n) {
    return testing::eventually([&] { return server_->connections() == n; }, testing::hang_ceiling);
  };
  RawConnection a(port_, unfinished);
  ASSERT_TRUE(connections_are(1));
  RawConnection b(port_, unfinished);
  RawConnection c(port_, unfinished);
  ASSERT_TRUE(connections_are(3));
  // A fourth: the oldest waiting one (a) is closed for it, unanswered.
  RawConnection d(port_, unfinished);
  EXPECT_EQ(a.read_to_close(), "");
  EXPECT_EQ(server_->connections_evicted(), 1u);
  // The others are served when they finish their requests.
  for (auto* late : {&b, &c, &d}) {
    late->send(rest);
    EXPECT_EQ(late->read_to_close().rfind("HTTP/1.1 200 ", 0), 0u);
  }
  ASSERT_TRUE(connections_are(0));
  // Three event streams wait for nothing: a fourth connection finds none to evict and is
  // refused with 503.
  Viewers streams(port_, 3);
  ASSERT_TRUE(streams.reach(state_.version()));
  RawConnection refused(port_, "");
  EXPECT_EQ(refused.read_to_close().rfind("HTTP/1.1 503 ", 0), 0u);
  EXPECT_EQ(server_->connections_refused(), 1u);
  EXPECT_EQ(server_->connections_evicted(), 1u);
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
