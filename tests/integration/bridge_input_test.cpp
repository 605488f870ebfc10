// retreat-bridge refuses bad input with one line and exit code 2, and answers malformed or
// oversized HTTP requests with a 4xx while it keeps serving everyone else. Every request goes
// to 127.0.0.1, bounded in count and time. No DDS (the in-memory transport).

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "bridge_support.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using testing::ChildProcess;
namespace fs = std::filesystem;
namespace tb = testing::bridge;

std::string scenario_file() {
  // One file per test: ctest runs the tests of this file in parallel processes.
  const std::string path = ::testing::TempDir() + "/bridge_input_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml";
  std::ofstream(path) << "name: bridge-input\narena: {encounter_model: kinetic}\n";
  return path;
}

/// Runs the bridge to its exit (at most 20 s); returns the exit code and its whole output.
std::pair<int, std::string> run_to_exit(const std::vector<std::string>& args) {
  // One log per run: ctest runs the tests of this file in parallel processes.
  static int run = 0;
  const std::string log = ::testing::TempDir() + "/bridge_input_" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" +
                          std::to_string(++run) + ".log";
  std::vector<std::string> argv = {RETREAT_BRIDGE_BIN};
  argv.insert(argv.end(), args.begin(), args.end());
  return testing::run_to_exit(argv, log);
}

void expect_one_line_and_exit_2(const std::vector<std::string>& args, const std::string& expected) {
  const auto [code, text] = run_to_exit(args);
  EXPECT_EQ(code, 2) << text;
  EXPECT_NE(text.find(expected), std::string::npos) << "expected '" << expected << "' in: " << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << "not one line: " << text;
  EXPECT_EQ(text.rfind("retreat-bridge: ", 0), 0u) << text;
}

TEST(BridgeBadInput, AMalformedHttpAddressGivesOneLineAndExitCodeTwo) {
  const auto scenario = scenario_file();
  for (const char* bad : {"nonsense", "127.0.0.1", "127.0.0.1:99999", "127.0.0.1:80x", ":8080", "example.org:80"}) {
    expect_one_line_and_exit_2({"--scenario", scenario, "--dds", "inmemory", "--http", bad},
                               std::string("--http = '") + bad + "'");
  }
  expect_one_line_and_exit_2({"--scenario", scenario, "--dds", "inmemory", "--set", "bridge.http=localhost"},
                             "bridge.http");
}

TEST(BridgeBadInput, BeyondLoopbackWithoutATokenAndBadTlsOrTokenFilesGiveOneLineAndExitCodeTwo) {
  const auto scenario = scenario_file();
  const std::string dir = ::testing::TempDir() + "/bridge_input_tls";
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + "/" + name) << text;
    return dir + "/" + name;
  };
  const auto good_token = write("token", "0123456789abcdef0123\n");
  const std::vector<std::string> live = {"--scenario", scenario, "--dds", "inmemory"};
  const auto with = [&](std::vector<std::string> more) {
    auto args = live;
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  expect_one_line_and_exit_2(with({"--http", "0.0.0.0:0"}),
                             "--http = '0.0.0.0:0' is beyond loopback: give --token-file FILE");
  expect_one_line_and_exit_2(with({"--set", "bridge.http=10.1.2.3:8080"}), "bridge.http = '10.1.2.3:8080' is beyond loopback");
  expect_one_line_and_exit_2({"--replay", "/nonexistent.mcap", "--http", "0.0.0.0:0"}, "is beyond loopback");
  expect_one_line_and_exit_2(with({"--tls-cert", write("cert.pem", "x")}), "--tls-cert without --tls-key");
  expect_one_line_and_exit_2(with({"--tls-key", write("key.pem", "x")}), "--tls-key without --tls-cert");
  expect_one_line_and_exit_2(with({"--token-file", good_token, "--no-token"}), "--token-file and --no-token");
  expect_one_line_and_exit_2(with({"--token-file", dir + "/missing"}), "--token-file '" + dir + "/missing': cannot read it");
  expect_one_line_and_exit_2(with({"--token-file", write("short", "abc\n")}), "must be 16 to 4096 characters");
  expect_one_line_and_exit_2(with({"--token-file", write("spaces", "0123456789 abcdef0123\n")}), "with others");
  expect_one_line_and_exit_2(with({"--http", "127.0.0.1:0", "--tls-cert", dir + "/missing.pem", "--tls-key", dir + "/key.pem"}),
                             "TLS certificate '" + dir + "/missing.pem': cannot read it");
  expect_one_line_and_exit_2(with({"--http", "127.0.0.1:0", "--tls-cert", dir + "/cert.pem", "--tls-key", dir + "/key.pem"}),
                             "not a PEM certificate chain and its matching private key");
}

TEST(BridgeBadInput, APortAlreadyInUseGivesOneLineAndExitCodeTwo) {
  // Hold a port on 127.0.0.1 with a plain listening socket.
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  inet_pton(AF_INET, "127.0.0.1", &sa.sin_addr);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa), 0);
  ASSERT_EQ(::listen(fd, 1), 0);
  socklen_t length = sizeof sa;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &length);
  const int port = ntohs(sa.sin_port);
  expect_one_line_and_exit_2({"--scenario", scenario_file(), "--dds", "inmemory", "--http",
                              "127.0.0.1:" + std::to_string(port)},
                             "--http 127.0.0.1:" + std::to_string(port) + ": Address already in use");
  // A second bridge on a port the first one holds: the same.
  auto first = tb::start_bridge({"--scenario", scenario_file(), "--dds", "inmemory", "--http", "127.0.0.1:0"},
                                ::testing::TempDir() + "/bridge_input_first.log");
  ASSERT_FALSE(first.url.empty()) << testing::read_file(first.log);
  expect_one_line_and_exit_2({"--scenario", scenario_file(), "--dds", "inmemory", "--http",
                              "127.0.0.1:" + std::to_string(first.port)},
                             "Address already in use");
  EXPECT_EQ(first.process->stop(), 0);
  ::close(fd);
}

TEST(BridgeBadInput, OtherBadInputGivesOneLineAndExitCodeTwo) {
  const auto scenario = scenario_file();
  expect_one_line_and_exit_2({"--dds", "inmemory"}, "--scenario is required");
  expect_one_line_and_exit_2({"--scenario", ::testing::TempDir() + "/no_such.yaml"}, "no_such.yaml");
  expect_one_line_and_exit_2({"--scenario", scenario, "--dds", "carrier-pigeon"}, "dds.vendor");
  expect_one_line_and_exit_2({"--scenario", scenario, "--domain", "999"}, "dds.domain");
  expect_one_line_and_exit_2({"--scenario", scenario, "--set", "model.delta=-1"}, "model.delta");
  const std::string empty = ::testing::TempDir() + "/bridge_input_empty";
  fs::create_directories(empty);
  expect_one_line_and_exit_2({"--report", empty}, "no telemetry.csv");
}

TEST(BridgeBadRequests, MalformedAndOversizedRequestsGet4xxAndTheBridgeKeepsServing) {
  auto b = tb::start_bridge({"--scenario", scenario_file(), "--dds", "inmemory", "--http", "127.0.0.1:0"},
                            ::testing::TempDir() + "/bridge_bad_requests.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  const auto still_serving = [&] {
    const auto r = tb::get(b.port, "/api/state", std::chrono::seconds(60));
    return r && r->status == 200 && r->body.find("\"scenario\":\"bridge-input\"") != std::string::npos;
  };
  ASSERT_TRUE(still_serving());

  struct Case {
    const char* what;
    std::string request;
  };
  const std::string big(20000, 'a');
  const std::vector<Case> cases = {
      {"garbage request line", "HELLO\r\n\r\n"},
      {"no HTTP version", "GET /api/state\r\n\r\n"},
      {"unknown method", "BREW /api/state HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"request line over 8 KiB", "GET /" + big + " HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"header over 8 KiB", "GET /api/state HTTP/1.1\r\nHost: x\r\nX-Big: " + big + "\r\n\r\n"},
      {"body over 64 KiB", "POST /api/state HTTP/1.1\r\nHost: x\r\nContent-Length: 10000000\r\n\r\n" + big},
      {"bad content length", "POST /api/state HTTP/1.1\r\nHost: x\r\nContent-Length: lots\r\n\r\n"},
      {"unknown path", "GET /etc/passwd HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"path traversal", "GET /runs/../../etc/passwd HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"encoded traversal", "GET /runs/%2e%2e%2f%2e%2e%2fetc%2fpasswd HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"a run file without --out", "GET /runs/telemetry.csv HTTP/1.1\r\nHost: x\r\n\r\n"},
      {"bad range", "GET /app.js HTTP/1.1\r\nHost: x\r\nRange: bytes=99999999-\r\n\r\n"},
  };
  for (const auto& c : cases) {
    const auto answer = tb::raw_exchange(b.port, c.request, std::chrono::seconds(60));
    const int status = tb::status_of(answer);
    EXPECT_GE(status, 400) << c.what << ": " << answer.substr(0, 200);
    EXPECT_LT(status, 500) << c.what << ": " << answer.substr(0, 200);
    ASSERT_TRUE(still_serving()) << "after " << c.what;
  }

  // Clients that stall half-way through their headers do not stall anyone else: each is dropped
  // after the 2 s read timeout, and meanwhile others are served at once.
  std::vector<std::thread> stalled;
  for (int i = 0; i < 6; ++i) {
    stalled.emplace_back([&] { tb::raw_exchange(b.port, "GET /api/state HTTP/1.1\r\nHost: x\r\n", 4s, true); });
  }
  std::this_thread::sleep_for(200ms);
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(still_serving()) << "while clients stall";
  for (auto& t : stalled) t.join();

  EXPECT_TRUE(b.process->running());
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

}  // namespace
}  // namespace retreat
