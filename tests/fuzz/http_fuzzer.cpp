// libFuzzer target: what a client sends to retreat-bridge's HTTP server (docs/fuzzing.md). One
// bridge::Server in this process, as retreat-bridge serves it (a run directory, every route,
// and with the input's first byte odd, a bearer token), on 127.0.0.1 with real sockets. The rest
// of the input goes to it on a new connection, which is then half-closed; whatever the bytes
// (requests, several pipelined, malformed, cut short), the server answers and closes. Bugs: a
// crash, an answer that is not HTTP/1.x with a 1xx-4xx, 503 or 505 status (a 500 is an exception
// in a route), an exception that left a handler, or no close within 60 s (libFuzzer's -timeout).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include "retreat/bridge/live_state.hpp"
#include "retreat/bridge/server.hpp"

namespace {

using namespace retreat;

struct Bridge {
  explicit Bridge(const std::string& token) {
    telemetry::RunInfo run;
    run.scenario = "fuzz";
    run.area = 4.0;
    run.lambda_star = 1.0;
    run.half_x = 1.0;
    run.half_y = 1.0;
    state = std::make_unique<bridge::LiveState>(telemetry::Aggregator(run));
    wire::ArenaTelemetry t;
    t.tick = 3;
    t.time = 0.09;
    t.inside = 2;
    state->update([&](telemetry::Aggregator& a) { a.on_telemetry(t); });
    dir = std::filesystem::temp_directory_path() / ("http_fuzzer_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/telemetry.csv") << "tick,time,inside\n3,0.09,2\n";
    bridge::ServerOptions o;
    o.run_dir = dir;
    o.token = token;
    server = std::make_unique<bridge::Server>(*state, o);
    port = server->bind({"127.0.0.1", 0});
    serving = std::thread([this] { server->serve(); });
  }
  ~Bridge() {
    server->stop();
    serving.join();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  std::unique_ptr<bridge::LiveState> state;
  std::string dir;
  std::unique_ptr<bridge::Server> server;
  int port = 0;
  std::thread serving;
};

/// Sends @p bytes, half-closes, and returns everything the server sent until it closed.
std::string exchange(int port, std::string_view bytes) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) std::abort();
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0) std::abort();
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const auto n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server may close early (a request it refused)
    sent += static_cast<std::size_t>(n);
  }
  ::shutdown(fd, SHUT_WR);
  std::string answer;
  char buffer[65536];
  for (;;) {
    const auto n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;  // closed (or reset after a refusal)
    answer.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return answer;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Bridge open("");
  static Bridge guarded("fuzz-token-0123456789");
  if (size == 0) return 0;
  const auto& bridge = (data[0] & 1) != 0 ? guarded : open;
  const auto answer = exchange(bridge.port, std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1));
  if (bridge.server->handler_failures() != 0) std::abort();  // an exception left a handler
  if (answer.empty()) return 0;  // nothing complete was asked (or the client went first)
  // The first answer's status line.
  if (answer.rfind("HTTP/1.", 0) != 0 || answer.size() < 12) std::abort();
  const int status = std::atoi(answer.c_str() + 9);
  if (status < 100 || (status >= 500 && status != 503 && status != 505)) std::abort();
  return 0;
}
