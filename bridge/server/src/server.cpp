#include "retreat/bridge/server.hpp"

#include <httplib.h>
#include <sys/socket.h>

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <utility>

#include "retreat/bridge/json.hpp"
#include "retreat/report/report.hpp"
#include "retreat/report/web_assets.hpp"

namespace retreat::bridge {

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr const char* json_type = "application/json";
constexpr std::array<const char*, 7> run_files = {
    "telemetry.csv",  "agents.csv",       "summary.json", "scenario.yaml",
    "encounters.csv", "agent_status.csv", "report.html"};

void no_store(httplib::Response& res) { res.set_header("Cache-Control", "no-store"); }

void plain_error(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(message + "\n", "text/plain; charset=utf-8");
}

const char* reason(int status) {
  switch (status) {
    case 400:
      return "bad request";
    case 404:
      return "not found";
    case 405:
      return "method not allowed";
    case 413:
      return "payload too large";
    case 414:
      return "URI too long";
    case 416:
      return "range not satisfiable";
    case 431:
      return "request header fields too large";
    case 500:
      return "internal error";
    case 503:
      return "unavailable";
    default:
      return status >= 500 ? "server error" : "error";
  }
}

}  // namespace

bool is_run_file(const std::string& name) {
  for (const char* f : run_files) {
    if (name == f) return true;
  }
  return false;
}

namespace {

/// Plain HTTP, or HTTPS with the options' certificate and key.
std::unique_ptr<httplib::Server> make_http(const ServerOptions& o) {
  if (o.tls_cert.empty() && o.tls_key.empty()) return std::make_unique<httplib::Server>();
  if (o.tls_cert.empty() || o.tls_key.empty()) {
    throw std::invalid_argument("TLS needs a certificate and its private key (got only the " +
                                std::string(o.tls_cert.empty() ? "key" : "certificate") + ")");
  }
  for (const auto& [what, path] : {std::pair{"certificate", o.tls_cert}, std::pair{"private key", o.tls_key}}) {
    if (!std::ifstream(path)) throw std::invalid_argument(std::string("TLS ") + what + " '" + path + "': cannot read it");
  }
  auto https = std::make_unique<httplib::SSLServer>(o.tls_cert.c_str(), o.tls_key.c_str());
  if (!https->is_valid()) {
    throw std::invalid_argument("TLS certificate '" + o.tls_cert + "' and key '" + o.tls_key +
                                "': not a PEM certificate chain and its matching private key");
  }
  return https;
}

/// Whether two secrets are equal, in a time that does not depend on where they differ.
bool same_secret(std::string_view given, std::string_view secret) {
  if (secret.empty()) return false;
  unsigned diff = given.size() == secret.size() ? 0u : 1u;
  for (std::size_t i = 0; i < given.size(); ++i) {
    diff |= static_cast<unsigned char>(given[i]) ^ static_cast<unsigned char>(secret[i % secret.size()]);
  }
  return diff == 0;
}

/// The value of cookie @p name in a request's Cookie header ("a=1; b=2"), or empty.
std::string cookie(const httplib::Request& req, std::string_view name) {
  const auto header = req.get_header_value("Cookie");
  std::size_t at = 0;
  while (at < header.size()) {
    const auto end = std::min(header.find(';', at), header.size());
    auto pair = std::string_view(header).substr(at, end - at);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    if (pair.size() > name.size() && pair.substr(0, name.size()) == name && pair[name.size()] == '=') {
      return std::string(pair.substr(name.size() + 1));
    }
    at = end + 1;
  }
  return {};
}

constexpr std::string_view token_cookie = "retreat_token";

}  // namespace

struct Server::Impl {
  LiveState& state;
  ServerOptions options;
  std::unique_ptr<httplib::Server> server;
  httplib::Server& http;
  std::atomic<bool> stopping{false};
  std::array<std::atomic<std::uint64_t>, 6> responses{};
  std::atomic<bool> serving{false};
  bool bound = false;

  Impl(LiveState& s, ServerOptions o)
      : state(s), options(std::move(o)), server(make_http(options)), http(*server) {}
};

Server::Server(LiveState& state, ServerOptions options)
    : impl_(std::make_unique<Impl>(state, std::move(options))) {
  configure_connections();
  require_token();
  add_page_routes();
  add_state_routes();
  add_event_stream_route();
  add_run_file_routes();
}

/// Threads, limits, timeouts, socket options, response counting and error pages.
void Server::configure_connections() {
  auto& http = impl_->http;
  auto* impl = impl_.get();
  const auto threads = impl->options.threads;
  http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http.set_payload_max_length(impl->options.max_payload);
  http.set_read_timeout(impl->options.read_timeout);
  http.set_write_timeout(impl->options.write_timeout);
  http.set_keep_alive_timeout(impl->options.keep_alive_timeout.count());
  http.set_keep_alive_max_count(100);
  http.set_tcp_nodelay(true);
  // httplib's default also sets SO_REUSEPORT, with which a second server binds a port in use and
  // the kernel splits the connections between them: only SO_REUSEADDR here.
  http.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  http.set_logger([impl](const httplib::Request&, const httplib::Response& res) {
    const int cls = res.status / 100;
    if (cls >= 1 && cls <= 5) ++impl->responses[static_cast<std::size_t>(cls)];
  });
  http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) {
      res.set_content(std::to_string(res.status) + " " + reason(res.status) + "\n",
                      "text/plain; charset=utf-8");
    }
  });
  http.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        plain_error(res, 500, "500 internal error");
      });
  http.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
}

/// ServerOptions::token: every request carries it (a bearer header or the cookie), or gets 401;
/// GET /?token=TOKEN sets the cookie and sends the page to / without it.
void Server::require_token() {
  auto* impl = impl_.get();
  if (impl->options.token.empty()) return;
  const bool https = !impl->options.tls_cert.empty();
  impl->http.set_pre_routing_handler([impl, https](const httplib::Request& req, httplib::Response& res) {
    using Result = httplib::Server::HandlerResponse;
    const auto& token = impl->options.token;
    const auto refuse = [&res] {
      res.set_header("WWW-Authenticate", "Bearer realm=\"retreat-bridge\"");
      plain_error(res, 401, "401 a token is required: Authorization: Bearer TOKEN, or open /?token=TOKEN");
      return Result::Handled;
    };
    if (req.has_param("token") && req.method == "GET" && (req.path == "/" || req.path == "/index.html")) {
      if (!same_secret(req.get_param_value("token"), token)) return refuse();
      res.status = 303;
      res.set_header("Location", req.path);
      res.set_header("Set-Cookie", std::string(token_cookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict" +
                                       (https ? "; Secure" : ""));
      no_store(res);
      return Result::Handled;
    }
    constexpr std::string_view bearer = "Bearer ";
    const auto authorization = req.get_header_value("Authorization");
    const bool by_header = authorization.size() > bearer.size() && authorization.compare(0, bearer.size(), bearer) == 0 &&
                           same_secret(std::string_view(authorization).substr(bearer.size()), token);
    if (by_header || same_secret(cookie(req, token_cookie), token)) return Result::Unhandled;
    return refuse();
  });
}

/// The dashboard's page and its assets, embedded in the program.
void Server::add_page_routes() {
  auto& http = impl_->http;
  const auto asset = [](const std::string& name) {
    return [name](const httplib::Request&, httplib::Response& res) {
      const auto* a = report::find_web_asset(name);
      if (a == nullptr) return plain_error(res, 404, "404 not found");
      res.set_content(a->data.data(), a->data.size(), std::string(report::content_type_for(name)));
      res.set_header("Cache-Control", name == "index.html" ? "no-cache" : "max-age=300");
      if (name == "index.html") {
        res.set_header(
            "Content-Security-Policy",
            "default-src 'self'; img-src 'self' data:; style-src 'self' 'unsafe-inline'");
      }
    };
  };
  http.Get("/", asset("index.html"));
  http.Get("/index.html", asset("index.html"));
  for (const auto& a : report::web_assets()) {
    const std::string name(a.name);
    if (name == "index.html" || name.rfind("report", 0) == 0) continue;  // report.* are for files
    http.Get("/" + name, asset(name));
  }
}

/// The JSON API and the Prometheus metrics: /api/state, /api/history, /metrics.
void Server::add_state_routes() {
  auto& http = impl_->http;
  auto* impl = impl_.get();
  http.Get("/api/state", [impl](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    res.set_content(impl->state.state_text().first, json_type);
  });
  http.Get("/api/history", [impl](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    res.set_content(impl->state.history_text(), json_type);
  });
  http.Get("/metrics", [impl](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    res.set_content(impl->state.metrics_text([impl](telemetry::PrometheusWriter& out) {
      if (impl->options.extra_metrics) impl->options.extra_metrics(out);
    }),
                    telemetry::prometheus_content_type);
  });
  add_replay_routes();
}

/// /api/replay (retreat-bridge --replay): the position in the recording, and moving it.
///   GET  /api/replay                      {replaying: true, first_tick, last_tick, first_time,
///                                          last_time, tick, time, playing, speed}; a live bridge
///                                          {replaying: false}, and 409 to a POST
///   POST /api/replay?tick=N               seek (and pause)
///   POST /api/replay?play=1[&speed=S]     play at S simulated s per wall s (default 1)
///   POST /api/replay?play=0               pause
/// A bad parameter gets 400 with one line naming it and what is allowed.
void Server::add_replay_routes() {
  auto& http = impl_->http;
  auto* impl = impl_.get();
  const auto position_json = [](const ReplayPosition& p) {
    return nlohmann::json{{"replaying", true},          {"first_tick", p.first_tick}, {"last_tick", p.last_tick}, {"first_time", p.first_time},
                          {"last_time", p.last_time},   {"tick", p.tick},           {"time", p.time},
                          {"playing", p.playing},       {"speed", p.speed}}
        .dump();
  };
  http.Get("/api/replay", [impl, position_json](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    if (impl->options.replay == nullptr) return res.set_content(R"({"replaying":false})", json_type);
    res.set_content(position_json(impl->options.replay->position()), json_type);
  });
  http.Post("/api/replay", [impl, position_json](const httplib::Request& req, httplib::Response& res) {
    auto* player = impl->options.replay;
    if (player == nullptr) return plain_error(res, 409, "409 not replaying a recording (retreat-bridge --replay FILE)");
    for (const auto& [key, value] : req.params) {
      if (key != "tick" && key != "play" && key != "speed") {
        return plain_error(res, 400, "400 unknown parameter '" + key.substr(0, 64) + "': tick, play or speed");
      }
    }
    const auto number = [&](const std::string& key, double& out) {
      const auto value = req.get_param_value(key);
      const char* first = value.data();
      const auto [end, ec] = std::from_chars(first, first + value.size(), out);
      return ec == std::errc() && end == first + value.size() && std::isfinite(out);
    };
    if (req.has_param("tick")) {
      double tick = 0;
      if (!number("tick", tick) || tick != std::floor(tick) || std::abs(tick) > 9e15) {
        return plain_error(res, 400, "400 tick '" + req.get_param_value("tick").substr(0, 64) + "': a whole number");
      }
      player->seek(static_cast<std::int64_t>(tick));
    }
    if (req.has_param("play")) {
      const auto play = req.get_param_value("play");
      double speed = 1.0;
      if (req.has_param("speed") &&
          (!number("speed", speed) || speed <= 0.0 || speed > ReplayPlayer::max_speed)) {
        return plain_error(res, 400, "400 speed '" + req.get_param_value("speed").substr(0, 64) +
                                         "': more than 0 and at most " +
                                         std::to_string(static_cast<int>(ReplayPlayer::max_speed)));
      }
      if (play == "1") {
        player->play(speed);
      } else if (play == "0") {
        player->pause();
      } else {
        return plain_error(res, 400, "400 play '" + play.substr(0, 64) + "': 1 or 0");
      }
    } else if (req.has_param("speed")) {
      return plain_error(res, 400, "400 speed without play=1");
    }
    no_store(res);
    res.set_content(position_json(player->position()), json_type);
  });
}

/// /api/events: server-sent events, one per state change, at most max_event_streams at once.
void Server::add_event_stream_route() {
  auto& http = impl_->http;
  auto* impl = impl_.get();
  http.Get("/api/events", [this, impl](const httplib::Request&, httplib::Response& res) {
    if (event_streams_.fetch_add(1) >= impl->options.max_event_streams) {
      --event_streams_;
      res.set_header("Retry-After", "5");
      return plain_error(res, 503, "503 too many event streams");
    }
    no_store(res);
    res.set_header("X-Accel-Buffering", "no");
    struct Stream {
      std::uint64_t seen = ~std::uint64_t{0};
      Clock::time_point opened = Clock::now();
      Clock::time_point last_sent{};
      bool greeted = false;
    };
    auto stream = std::make_shared<Stream>();
    res.set_chunked_content_provider(
        "text/event-stream",
        [impl, stream](std::size_t, httplib::DataSink& sink) {
          const auto& o = impl->options;
          if (!stream->greeted) {
            stream->greeted = true;
            const std::string hello = "retry: 1000\n\n";
            if (!sink.write(hello.data(), hello.size())) return false;
          }
          for (;;) {
            if (impl->stopping.load() || Clock::now() - stream->opened > o.event_stream_lifetime) {
              sink.done();
              return true;
            }
            const auto since = Clock::now() - stream->last_sent;
            if (since < o.event_min_interval) {
              std::this_thread::sleep_for(o.event_min_interval - since);
              continue;
            }
            const auto v = impl->state.wait_for_change(stream->seen, 250ms);
            if (v != stream->seen) {
              const auto [text, version] = impl->state.state_text();
              stream->seen = version;
              stream->last_sent = Clock::now();
              const std::string event =
                  "event: state\nid: " + std::to_string(version) + "\ndata: " + text + "\n\n";
              return sink.write(event.data(), event.size());
            }
            if (Clock::now() - stream->last_sent > o.event_keep_alive) {
              stream->last_sent = Clock::now();
              const std::string comment = ": idle\n\n";
              return sink.write(comment.data(), comment.size());
            }
          }
        },
        [this](bool) { --event_streams_; });
  });
}

/// The run directory: /api/runs lists its files, /runs/<file> serves one, /report renders one.
void Server::add_run_file_routes() {
  auto& http = impl_->http;
  auto* impl = impl_.get();
  http.Get("/api/runs", [impl](const httplib::Request&, httplib::Response& res) {
    no_store(res);
    nlohmann::json j;
    j["files"] = nlohmann::json::array();
    if (!impl->options.run_dir.empty()) {
      for (const char* f : run_files) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(impl->options.run_dir + "/" + f, ec);
        if (!ec)
          j["files"].push_back({{"name", f}, {"size", size}, {"url", std::string("/runs/") + f}});
      }
    }
    j["recording"] = !impl->options.run_dir.empty();
    res.set_content(j.dump(), json_type);
  });

  http.Get(R"(/runs/([A-Za-z0-9_.-]{1,64}))",
           [impl](const httplib::Request& req, httplib::Response& res) {
             const std::string name = req.matches[1];
             if (impl->options.run_dir.empty())
               return plain_error(res, 404, "404 no run directory (start with --out DIR)");
             if (!is_run_file(name)) return plain_error(res, 404, "404 not a run file");
             const std::string path = impl->options.run_dir + "/" + name;
             auto file = std::make_shared<std::ifstream>(path, std::ios::binary);
             std::error_code ec;
             const auto size = std::filesystem::file_size(path, ec);
             if (!*file || ec)
               return plain_error(res, 404, "404 " + name + " is not in the run directory (yet)");
             no_store(res);
             if (name != "report.html")
               res.set_header("Content-Disposition", "attachment; filename=\"" + name + "\"");
             // The arena may still be appending: serve the size seen now.
             res.set_content_provider(
                 static_cast<std::size_t>(size), std::string(report::content_type_for(name)),
                 [file](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                   char buffer[16384];
                   file->seekg(static_cast<std::streamoff>(offset));
                   const auto n = std::min(length, sizeof buffer);
                   file->read(buffer, static_cast<std::streamsize>(n));
                   const auto got = static_cast<std::size_t>(file->gcount());
                   if (got == 0) return false;
                   return sink.write(buffer, got);
                 });
           });

  http.Get("/report", [impl](const httplib::Request&, httplib::Response& res) {
    if (impl->options.run_dir.empty())
      return plain_error(res, 404, "404 no run directory (start with --out DIR)");
    no_store(res);
    try {
      res.set_content(report::render_report(impl->options.run_dir), "text/html; charset=utf-8");
    } catch (const std::exception& e) {
      plain_error(res, 409, std::string("409 no report yet: ") + e.what());
    }
  });
}

Server::~Server() { stop(); }

int Server::bind(const HttpAddress& address) {
  auto& http = impl_->http;
  int port = address.port;
  bool ok = false;
  if (port == 0) {
    port = http.bind_to_any_port(address.host);
    ok = port > 0;
  } else {
    ok = http.bind_to_port(address.host, port);
  }
  if (!ok) {
    auto why = probe_bind(address);
    if (why.empty()) why = "cannot listen";
    throw std::runtime_error(address.host + ":" + std::to_string(address.port) + ": " + why);
  }
  impl_->bound = true;
  return port;
}

void Server::serve() {
  if (!impl_->bound) throw std::logic_error("Server::serve() before bind()");
  impl_->serving.store(true);
  if (!impl_->stopping.load()) impl_->http.listen_after_bind();
  impl_->serving.store(false);
}

void Server::stop() {
  impl_->stopping.store(true);
  // serve() may be between its start and httplib's running state: wait for either end.
  while (impl_->serving.load() && !impl_->http.is_running()) std::this_thread::sleep_for(1ms);
  if (impl_->http.is_running()) impl_->http.stop();
}

std::array<std::uint64_t, 6> Server::responses() const {
  std::array<std::uint64_t, 6> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = impl_->responses[i].load();
  return out;
}

}  // namespace retreat::bridge
