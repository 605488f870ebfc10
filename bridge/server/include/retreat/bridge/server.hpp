#pragma once
/// @file
/// The bridge's HTTP server: the dashboard, the JSON API, server-sent events, Prometheus metrics
/// and the run directory's files, over Boost.Beast on Boost.Asio (event-driven: a connection
/// costs a socket and a buffer, never a thread). Nothing here touches DDS; requests read the
/// mutex-protected LiveState.
///
///   GET /                  the dashboard (index.html, app.js, style.css, vendor/uPlot.*)
///   GET /api/state         current snapshot (JSON)
///   GET /api/history       time series (JSON, one array per field)
///   GET /api/events        server-sent events: `event: state` with the snapshot on each change
///                          (at most one per event_min_interval), a comment line when idle
///   GET /api/runs          the run directory's downloadable files (JSON)
///   GET /metrics           Prometheus text format 0.0.4
///   GET /runs/<file>       telemetry.csv, agents.csv, summary.json, scenario.yaml,
///                          encounters.csv, agent_status.csv, report.html (from --out)
///   GET /report            a report of the run directory rendered now (HTML), on a worker
///   GET, POST /api/replay  with --replay: the position in the recording, seek, play, pause
///                          (server.cpp, replay_route)
/// HEAD is answered wherever GET is, ranges (`Range: bytes=`) on the page's files.
///
/// Optionally HTTPS and a bearer token (ServerOptions::tls_cert, tls_key, token).
///
/// Clients that misbehave cost the others nothing (docs/security.md, "Clients that misbehave"):
/// a request's line and headers must arrive within read_timeout of the server starting to wait
/// for them, and its body too; a request line over 8 KiB gets 414, headers over 8 KiB 431, a
/// body over max_payload 413. A new connection from an address that holds
/// max_connections_per_address connections closes the oldest of them that waits for a request
/// (stalled, trickling or idle); if none waits, or the server holds max_connections, the new
/// one is answered 503 and closed. A report asked for while max_queued reports wait gets 503.
///
/// Event streams: the broadcaster looks at the state every event_min_interval; a changed state
/// is made into one event whose bytes are written to every stream. A stream still writing an
/// older event gets the newest when that write ends (states in between are skipped, never
/// queued); a stream whose write stalls for write_timeout is closed.

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "retreat/bridge/address.hpp"
#include "retreat/bridge/live_state.hpp"
#include "retreat/bridge/replay_player.hpp"

namespace retreat::bridge {

struct ServerOptions {
  std::string run_dir;  ///< files under /runs/ (empty: none)
  std::size_t io_threads = 2;  ///< threads running the event loop (serve() is one of them)
  std::size_t workers = 1;     ///< threads rendering reports (/report)
  std::size_t max_queued = 8;  ///< reports waiting for a worker before /report answers 503
  std::size_t max_connections = 4096;  ///< at most the open-file limit less 128
  std::size_t max_connections_per_address = 256;
  std::size_t max_event_streams = 1024;
  std::size_t max_payload = 64 * 1024;
  std::size_t max_requests_per_connection = 100;
  /// Time for a request's line and headers (and again for its body), and for a TLS handshake;
  /// also how long a kept-alive connection may idle before its next request.
  std::chrono::milliseconds read_timeout{2000};
  /// Time for one write; a reader that takes no bytes for that long is dropped.
  std::chrono::milliseconds write_timeout{5000};
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
  std::size_t event_streams() const;
  /// Connections open now.
  std::size_t connections() const;
  /// Connections refused (answered 503 and closed): the server held max_connections, or their
  /// address held max_connections_per_address and none of them was waiting for a request.
  std::uint64_t connections_refused() const;
  /// Connections closed to make room for a new one from the same address (the oldest of the
  /// address's connections waiting for a request).
  std::uint64_t connections_evicted() const;
  /// Handlers that threw (a bug: the connection is dropped and the server serves on; the first
  /// is said on stderr).
  std::uint64_t handler_failures() const;

  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace retreat::bridge
