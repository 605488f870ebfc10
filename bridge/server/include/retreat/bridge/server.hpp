#pragma once
/// @file
/// The bridge's HTTP server (cpp-httplib): the dashboard, the JSON API, server-sent events,
/// Prometheus metrics and the run directory's files. Requests are served on httplib's worker
/// threads from the mutex-protected LiveState; nothing here touches DDS.
///
///   GET /                  the dashboard (index.html, app.js, style.css, vendor/uPlot.*)
///   GET /api/state         current snapshot (JSON)
///   GET /api/history       time series (JSON, one array per field)
///   GET /api/events        server-sent events: `event: state` with the snapshot on each change
///                          (at most 10 per second), a comment line every 15 s when idle
///   GET /api/runs          the run directory's downloadable files (JSON)
///   GET /metrics           Prometheus text format 0.0.4
///   GET /runs/<file>       telemetry.csv, agents.csv, summary.json, scenario.yaml,
///                          encounters.csv, agent_status.csv, report.html (from --out)
///   GET /report            a report of the run directory rendered now (HTML)
///   GET, POST /api/replay  with --replay: the position in the recording, seek, play, pause
///                          (server.cpp, add_replay_routes)
///
/// Optionally HTTPS and a bearer token (ServerOptions::tls_cert, tls_key, token).
///
/// Limits: request bodies over 64 KiB get 413, request lines over 8 KiB 414, headers over
/// 8 KiB 400; a client that stalls is dropped after 2 s; at most 8 event streams at once (503
/// beyond), each closed after 5 minutes (EventSource reconnects).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "retreat/bridge/address.hpp"
#include "retreat/bridge/live_state.hpp"
#include "retreat/bridge/replay_player.hpp"

namespace retreat::bridge {

struct ServerOptions {
  std::string run_dir;  ///< files under /runs/ (empty: none)
  std::size_t threads = 16;
  std::size_t max_event_streams = 8;
  std::size_t max_payload = 64 * 1024;
  std::chrono::seconds read_timeout{2};
  std::chrono::seconds write_timeout{5};
  std::chrono::seconds keep_alive_timeout{2};
  std::chrono::seconds event_stream_lifetime{300};
  std::chrono::milliseconds event_min_interval{100};
  std::chrono::seconds event_keep_alive{15};
  /// More metric families after the swarm's (e.g. the receiver's counters).
  std::function<void(telemetry::PrometheusWriter&)> extra_metrics;
  /// With --replay: the player /api/replay moves (must outlive the server); null when live.
  ReplayPlayer* replay = nullptr;
  /// HTTPS with this certificate chain and private key (PEM files), or plain HTTP when both are
  /// empty (docs/security.md, "The bridge beyond loopback").
  std::string tls_cert;
  std::string tls_key;
  /// Every request must carry it (empty: none is asked for): `Authorization: Bearer TOKEN` (a
  /// Prometheus scrape, curl), or the cookie `retreat_token`, which a page opened as
  /// `/?token=TOKEN` gets (303 to `/`, HttpOnly, SameSite=Strict, Secure over HTTPS), so that
  /// the dashboard's own requests and its event stream carry it. Anything else gets 401.
  std::string token;
};

/// Files a run directory may serve, and nothing else.
bool is_run_file(const std::string& name);

class Server {
 public:
  /// @throws std::invalid_argument with one line when the TLS certificate or key cannot be used.
  Server(LiveState& state, ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds the listening socket; returns the port (the chosen one for port 0).
  /// @throws std::runtime_error with one line (the address and errno's text) on failure.
  int bind(const HttpAddress& address);
  /// Serves until stop(); call bind() first. Blocks.
  void serve();
  /// Ends every event stream and stops serving (any thread). serve() returns soon after.
  void stop();
  /// Requests answered so far, by status class (index 1..5 for 1xx..5xx).
  std::array<std::uint64_t, 6> responses() const;
  std::size_t event_streams() const { return event_streams_.load(); }

 private:
  void configure_connections();
  void add_page_routes();
  void add_state_routes();
  void add_event_stream_route();
  void add_run_file_routes();
  void add_replay_routes();
  void require_token();

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::atomic<std::size_t> event_streams_{0};
};

}  // namespace retreat::bridge
