// retreat-bridge: what the swarm is doing, for people and for tools.
//
// Reads:  <prefix>/arena_telemetry   (ground truth, keyed by arena id; transient-local)
//         <prefix>/poses             (positions for display, keyed by arena id; transient-local)
//         <prefix>/agent_status      (each agent's estimate, ε, window count; transient-local)
//         Never a robot's own topics (<prefix>/robot_<id>/...).
// Writes: HTTP on bridge.http (--http): the dashboard, /api/state, /api/history, /api/events,
//         /metrics, /runs/<file>, /report (see bridge/server/include/retreat/bridge/server.hpp).
//         With --out DIR: DIR/agent_status.csv (every status received) and DIR/report.html, when
//         the arena's summary.json appears and again on SIGINT/SIGTERM.
//
// retreat-bridge --replay FILE serves the same dashboard for a recording (retreat-record's), with
// a time slider (/api/replay), and joins no DDS.
//
// retreat-bridge --report DIR writes DIR/report.html for a finished run directory (or one with
// seed_<n>/ run directories) and exits.
//
// Exit codes: 0 stopped by SIGINT/SIGTERM (or --report done); 2 bad input at start-up, including
// a malformed --http and a port that cannot be bound; 1 middleware or file failure.

#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <thread>
#include <variant>

#include "retreat/bridge/command_line.hpp"
#include "retreat/bridge/address.hpp"
#include "retreat/bridge/live_state.hpp"
#include "retreat/bridge/receiver.hpp"
#include "retreat/bridge/server.hpp"
#include "retreat/bridge/replay_player.hpp"
#include "retreat/core/paths.hpp"
#include "retreat/replay/recording.hpp"
#include "retreat/report/report.hpp"
#include "retreat/report/run_info.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/transport/factory.hpp"

namespace {

using namespace retreat;
namespace fs = std::filesystem;

int fail(int code, const std::string& message) {
  std::fprintf(stderr, "retreat-bridge: %s\n", message.c_str());
  return code;
}

/// Writes the report, saying so on stderr; a failure is reported, never fatal.
void report(const std::string& dir) {
  try {
    const auto path = report::write_report(dir);
    std::fprintf(stderr, "retreat-bridge: wrote %s\n", path.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-bridge: no report: %s\n", e.what());
  }
}

/// Raises the soft limit of open files to the hard one: every HTTP connection is a file, and the
/// server holds at most as many as the soft limit leaves (ServerOptions::max_connections).
void raise_open_file_limit() {
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < files.rlim_max) {
    files.rlim_cur = files.rlim_max;
    setrlimit(RLIMIT_NOFILE, &files);
  }
}

/// The HTTP server with @p options and the command line's HTTPS and token, bound to its address;
/// @p port is set to the port bound. @throws std::invalid_argument with one line (bad input).
std::unique_ptr<bridge::Server> bound_server(bridge::LiveState& state, bridge::ServerOptions options,
                                             const bridge::BridgeCommandLine& command_line, int& port) {
  options.tls_cert = command_line.tls_cert;
  options.tls_key = command_line.tls_key;
  options.token = command_line.token;
  raise_open_file_limit();
  auto server = std::make_unique<bridge::Server>(state, std::move(options));
  try {
    port = server->bind(command_line.address);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(command_line.address_origin + " " + e.what());
  }
  return server;
}

/// Serves on a thread of its own from construction until stop() (or destruction).
class ServingThread {
 public:
  explicit ServingThread(bridge::Server& server) : server_(server), thread_([this] { server_.serve(); }) {}
  ~ServingThread() { stop(); }
  ServingThread(const ServingThread&) = delete;
  ServingThread& operator=(const ServingThread&) = delete;
  void stop() {
    if (!thread_.joinable()) return;
    server_.stop();
    thread_.join();
  }

 private:
  bridge::Server& server_;
  std::thread thread_;
};

/// Blocks until SIGINT or SIGTERM (blocked beforehand in @p signals) and says which.
void wait_for_stop_signal(const sigset_t& signals) {
  int signo = 0;
  sigwait(&signals, &signo);
  std::fprintf(stderr, "retreat-bridge: stopping (signal %d)\n", signo);
}

/// The line tools and tests wait for: the URL served on @p port.
void announce(const bridge::BridgeCommandLine& command_line, int port) {
  std::printf("retreat-bridge: serving %s://%s:%d/%s\n", command_line.tls_cert.empty() ? "http" : "https",
              command_line.address.host.c_str(), port,
              command_line.token.empty() ? "" : " (a token is required: open /?token=TOKEN)");
  std::fflush(stdout);
}

/// The summary.json's modification time, if it exists.
std::optional<fs::file_time_type> summary_time(const std::string& dir) {
  std::error_code ec;
  const auto t = fs::last_write_time(dir + "/summary.json", ec);
  if (ec) return std::nullopt;
  return t;
}

/// --report DIR: writes DIR/report.html and returns the exit code.
int write_report_only(const std::string& dir) {
  try {
    const auto path = report::write_report(dir);
    std::printf("retreat-bridge: wrote %s\n", path.c_str());
    return 0;
  } catch (const std::invalid_argument& e) {
    return fail(2, std::string("--report ") + dir + ": " + e.what());
  } catch (const std::exception& e) {
    return fail(2, std::string("--report: ") + e.what());
  }
}

/// Every thread (DDS's, httplib's, ours) inherits this mask; main takes the signals with
/// sigwait. SIGPIPE: a client that went away must not end the program.
sigset_t block_stop_signals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
  return stop_signals;
}

/// The bridge's own metrics beside the swarm's: HTTP responses, event streams, matched writers,
/// invalid samples. Reads the server and the receiver through pointers set once they exist.
std::function<void(telemetry::PrometheusWriter&)> bridge_metrics(
    const bridge::Server* const& server, const std::unique_ptr<bridge::Receiver>& receiver) {
  return [&server, &receiver](telemetry::PrometheusWriter& out) {
    if (server != nullptr) {
      const auto r = server->responses();
      out.family("retreat_bridge_http_responses_total", "counter",
                 "HTTP responses by status class.");
      for (std::size_t c = 1; c < r.size(); ++c) {
        out.sample(static_cast<double>(r[c]), {{"code", std::to_string(c) + "xx"}});
      }
      out.family("retreat_bridge_event_streams", "gauge", "Open server-sent event streams.");
      out.sample(static_cast<double>(server->event_streams()));
      out.family("retreat_bridge_http_connections", "gauge", "Open HTTP connections.");
      out.sample(static_cast<double>(server->connections()));
      out.family("retreat_bridge_http_connections_refused_total", "counter",
                 "HTTP connections refused (503): the bridge, or their address with none waiting, held its limit.");
      out.sample(static_cast<double>(server->connections_refused()));
      out.family("retreat_bridge_http_connections_evicted_total", "counter",
                 "HTTP connections waiting for a request, closed to make room for a new one from "
                 "the same address.");
      out.sample(static_cast<double>(server->connections_evicted()));
      out.family("retreat_bridge_http_handler_failures_total", "counter",
                 "HTTP handlers that threw (a bug; the connection was dropped).");
      out.sample(static_cast<double>(server->handler_failures()));
    }
    if (!receiver) return;
    const auto m = receiver->matched();
    out.family("retreat_bridge_writers_matched", "gauge",
               "Remote writers matched with the bridge's readers.");
    out.sample(static_cast<double>(m[0]), {{"topic", "arena_telemetry"}});
    out.sample(static_cast<double>(m[1]), {{"topic", "poses"}});
    out.sample(static_cast<double>(m[2]), {{"topic", "agent_status"}});
    out.family("retreat_bridge_samples_invalid_total", "counter",
               "Samples the readers dropped as invalid.");
    out.sample(static_cast<double>(receiver->dropped()));
  };
}

/// --out DIR: the recorder of agent statuses in DIR (made if missing); none without --out.
/// @throws std::runtime_error naming DIR when it cannot be made or written.
std::unique_ptr<bridge::StatusRecorder> open_recorder(const std::string& out_dir) {
  if (out_dir.empty()) return nullptr;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec)
    throw std::runtime_error("--out '" + out_dir +
                             "': cannot create the directory: " + ec.message());
  return std::make_unique<bridge::StatusRecorder>(out_dir);
}

/// Serves the dashboard and records until SIGINT or SIGTERM; returns the exit code.
int serve(const bridge::BridgeCommandLine& command_line) {
  const auto& s = command_line.scenario;
  const auto& out_dir = command_line.out_dir;
  sigset_t stop_signals = block_stop_signals();

  std::unique_ptr<bridge::StatusRecorder> recorder;
  try {
    recorder = open_recorder(out_dir);
  } catch (const std::exception& e) {
    return fail(2, e.what());
  }

  bridge::LiveState state{telemetry::Aggregator(report::run_info(s))};
  std::unique_ptr<bridge::Receiver> receiver;
  const bridge::Server* serving_server = nullptr;
  bridge::ServerOptions options;
  options.run_dir = out_dir;
  options.extra_metrics = bridge_metrics(serving_server, receiver);
  std::unique_ptr<bridge::Server> server;
  int port = 0;
  try {
    server = bound_server(state, std::move(options), command_line, port);
  } catch (const std::invalid_argument& e) {
    return fail(2, e.what());
  }
  serving_server = server.get();

  std::unique_ptr<transport::Transport> transport;
  try {
    transport = transport::make_transport(
        retreat::name_of(s.dds.vendor), scenario::participant_options(s, "retreat-bridge", "retreat:bridge", "bridge"));
    receiver = std::make_unique<bridge::Receiver>(*transport, s.dds.prefix, state, recorder.get());
  } catch (const std::invalid_argument& e) {
    return fail(2, e.what());
  } catch (const std::exception& e) {
    return fail(1, e.what());
  }

  std::atomic<bool> stop{false};
  // The end of the run: the arena writes summary.json into the run directory last.
  auto reported_summary = out_dir.empty() ? std::nullopt : summary_time(out_dir);
  std::thread receiving([&] {
    receiver->run(stop, [&] {
      if (out_dir.empty()) return;
      const auto t = summary_time(out_dir);
      if (t && t != reported_summary) {
        reported_summary = t;
        report(out_dir);
      }
    });
  });
  ServingThread serving(*server);
  announce(command_line, port);
  std::fprintf(stderr, "retreat-bridge: %s on %s domain %d, prefix '%s'%s%s\n", s.name.c_str(),
               std::string(retreat::name_of(s.dds.vendor)).c_str(), s.dds.domain, s.dds.prefix.c_str(),
               out_dir.empty() ? "" : ", recording into ", out_dir.c_str());

  wait_for_stop_signal(stop_signals);
  stop.store(true);
  serving.stop();
  receiving.join();
  receiver.reset();
  transport.reset();
  if (recorder) recorder->flush();
  if (!out_dir.empty() && retreat::exists(out_dir + "/telemetry.csv")) report(out_dir);
  return 0;
}

/// --replay FILE: serves the dashboard of a recording, moved by /api/replay, until SIGINT or
/// SIGTERM; returns the exit code.
int serve_replay(const bridge::BridgeCommandLine& command_line) {
  sigset_t stop_signals = block_stop_signals();
  replay::Recording recording;
  try {
    recording = replay::load_recording(command_line.replay);
  } catch (const replay::RecordingError& e) {
    return fail(2, std::string("--replay: ") + e.what());
  }
  const auto& s = recording.scenario;
  bridge::LiveState state{telemetry::Aggregator(report::run_info(s))};
  const auto samples = [](const auto& recorded) {
    std::vector<std::decay_t<decltype(recorded.front().sample)>> out;
    out.reserve(recorded.size());
    for (const auto& r : recorded) out.push_back(r.sample);
    return out;
  };
  std::optional<bridge::ReplayPlayer> player;
  try {
    player.emplace(state, report::run_info(s), samples(recording.telemetry), samples(recording.poses),
                   samples(recording.statuses));
  } catch (const std::invalid_argument& e) {
    return fail(2, "--replay '" + command_line.replay + "': " + e.what());
  }
  bridge::ServerOptions options;
  options.replay = &*player;
  std::unique_ptr<bridge::Server> server;
  int port = 0;
  try {
    server = bound_server(state, std::move(options), command_line, port);
  } catch (const std::invalid_argument& e) {
    return fail(2, e.what());
  }
  std::atomic<bool> stop{false};
  std::thread playing([&] {
    while (!stop.load()) {
      player->advance(std::chrono::steady_clock::now());
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  ServingThread serving(*server);
  announce(command_line, port);
  const auto p = player->position();
  std::fprintf(stderr, "retreat-bridge: replaying %s (%s, ticks %lld..%lld, %zu telemetry samples)\n",
               command_line.replay.c_str(), s.name.c_str(), static_cast<long long>(p.first_tick),
               static_cast<long long>(p.last_tick), recording.telemetry.size());
  wait_for_stop_signal(stop_signals);
  stop.store(true);
  serving.stop();
  playing.join();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = scenario::parse_or_report(
      "retreat-bridge", [&] { return bridge::parse_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& command_line = std::get<bridge::BridgeCommandLine>(parsed);
  if (!command_line.report_dir.empty()) return write_report_only(command_line.report_dir);
  if (!command_line.replay.empty()) return serve_replay(command_line);
  if (command_line.print_config) {
    std::cout << scenario::dump(command_line.scenario);
    return 0;
  }
  return serve(command_line);
}
