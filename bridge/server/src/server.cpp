#include "retreat/bridge/server.hpp"

#include <openssl/ssl.h>
#include <sys/resource.h>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <list>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

#include "retreat/bridge/json.hpp"
#include "retreat/report/report.hpp"
#include "retreat/report/web_assets.hpp"

namespace retreat::bridge {

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr const char* json_type = "application/json";
constexpr const char* text_type = "text/plain; charset=utf-8";
constexpr std::array<const char*, 7> run_files = {
    "telemetry.csv",  "agents.csv",       "summary.json", "scenario.yaml",
    "encounters.csv", "agent_status.csv", "report.html"};
constexpr std::size_t max_request_line = 8 * 1024;
constexpr std::size_t max_header = 8 * 1024;  // the request line and the header fields
constexpr std::string_view token_cookie = "retreat_token";

const char* reason(unsigned status) {
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
    case 505:
      return "HTTP version not supported";
    default:
      return status >= 500 ? "server error" : "error";
  }
}

/// A request as the routes see it: the method, the percent-decoded path and query, the fields.
struct Request {
  http::verb method;
  std::string path;
  std::vector<std::pair<std::string, std::string>> query;
  const http::fields& fields;

  bool has(std::string_view key) const {
    for (const auto& [k, v] : query) {
      if (k == key) return true;
    }
    return false;
  }
  /// The first value of @p key, or empty.
  std::string param(std::string_view key) const {
    for (const auto& [k, v] : query) {
      if (k == key) return v;
    }
    return {};
  }
  std::string header(http::field name) const {
    const auto it = fields.find(name);
    return it == fields.end() ? std::string() : std::string(it->value());
  }
};

/// What a route answers: a body (or a file of the run directory), or an event stream; or work
/// for a worker thread that fills the answer in.
struct Response {
  unsigned status = 200;
  std::string content_type;
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string file;        ///< serve this file (its size when opened) instead of the body
  bool ranges = false;     ///< a `Range: bytes=` request gets its part of the body
  bool event_stream = false;
  std::function<void(Response&)> on_worker;

  void set(std::string name, std::string value) { headers.emplace_back(std::move(name), std::move(value)); }
  void content(std::string text, std::string type) {
    body = std::move(text);
    content_type = std::move(type);
  }
  void error(unsigned code, const std::string& message) {
    status = code;
    content(message + "\n", text_type);
  }
  void no_store() { set("Cache-Control", "no-store"); }
};

using Handler = std::function<void(const Request&, Response&)>;

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// %XX decoded (and '+' as a space in a query); nullopt for a broken escape.
std::optional<std::string> percent_decoded(std::string_view in, bool plus_is_space) {
  std::string out;
  out.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '%') {
      if (i + 2 >= in.size()) return std::nullopt;
      const int hi = hex_digit(in[i + 1]);
      const int lo = hex_digit(in[i + 2]);
      if (hi < 0 || lo < 0) return std::nullopt;
      out.push_back(static_cast<char>(hi * 16 + lo));
      i += 2;
    } else {
      out.push_back(c == '+' && plus_is_space ? ' ' : c);
    }
  }
  return out;
}

/// Splits a request target into its decoded path and query; false for a broken escape.
bool parse_target(std::string_view target, std::string& path,
                  std::vector<std::pair<std::string, std::string>>& query) {
  const auto mark = target.find('?');
  auto decoded = percent_decoded(target.substr(0, mark), false);
  if (!decoded) return false;
  path = std::move(*decoded);
  if (mark == std::string_view::npos) return true;
  auto rest = target.substr(mark + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const auto pair = rest.substr(0, amp);
    rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
    if (pair.empty()) continue;
    const auto eq = pair.find('=');
    auto key = percent_decoded(pair.substr(0, eq), true);
    auto value = percent_decoded(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1), true);
    if (!key || !value) return false;
    query.emplace_back(std::move(*key), std::move(*value));
  }
  return true;
}

/// `Range: bytes=A-B`, `A-` or `-N` on a body: 206 with its part, or 416 when it starts past
/// the end. Other units, several ranges or a malformed one: the whole body (RFC 9110 §14.2).
void apply_range(std::string_view range, Response& res) {
  constexpr std::string_view unit = "bytes=";
  if (range.substr(0, unit.size()) != unit || range.find(',') != std::string_view::npos) return;
  const auto spec = range.substr(unit.size());
  const auto dash = spec.find('-');
  if (dash == std::string_view::npos) return;
  const auto number = [](std::string_view text, std::uint64_t& out) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return !text.empty() && ec == std::errc() && end == text.data() + text.size();
  };
  const std::uint64_t size = res.body.size();
  std::uint64_t first = 0;
  std::uint64_t last = size == 0 ? 0 : size - 1;
  if (dash == 0) {  // the last N bytes
    std::uint64_t n = 0;
    if (!number(spec.substr(1), n)) return;
    if (n == 0 || size == 0) first = size;  // unsatisfiable
    else first = size - std::min(n, size);
  } else {
    if (!number(spec.substr(0, dash), first)) return;
    if (dash + 1 < spec.size()) {
      std::uint64_t given = 0;
      if (!number(spec.substr(dash + 1), given) || given < first) return;
      last = std::min(given, last);
    }
  }
  if (first >= size) {
    res.error(416, "416 range not satisfiable: the body has " + std::to_string(size) + " bytes");
    res.set("Content-Range", "bytes */" + std::to_string(size));
    return;
  }
  res.status = 206;
  res.set("Content-Range", "bytes " + std::to_string(first) + "-" + std::to_string(last) + "/" + std::to_string(size));
  res.body = res.body.substr(first, last - first + 1);
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

/// The value of cookie @p name in a Cookie header ("a=1; b=2"), or empty.
std::string cookie(std::string_view header, std::string_view name) {
  std::size_t at = 0;
  while (at < header.size()) {
    const auto end = std::min(header.find(';', at), header.size());
    auto pair = header.substr(at, end - at);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    if (pair.size() > name.size() && pair.substr(0, name.size()) == name && pair[name.size()] == '=') {
      return std::string(pair.substr(name.size() + 1));
    }
    at = end + 1;
  }
  return {};
}

/// HTTPS with the options' certificate and key, or none for plain HTTP.
std::unique_ptr<asio::ssl::context> tls_context(const ServerOptions& o) {
  if (o.tls_cert.empty() && o.tls_key.empty()) return nullptr;
  if (o.tls_cert.empty() || o.tls_key.empty()) {
    throw std::invalid_argument("TLS needs a certificate and its private key (got only the " +
                                std::string(o.tls_cert.empty() ? "key" : "certificate") + ")");
  }
  for (const auto& [what, path] : {std::pair{"certificate", o.tls_cert}, std::pair{"private key", o.tls_key}}) {
    if (!std::ifstream(path)) throw std::invalid_argument(std::string("TLS ") + what + " '" + path + "': cannot read it");
  }
  auto context = std::make_unique<asio::ssl::context>(asio::ssl::context::tls_server);
  context->set_options(asio::ssl::context::default_workarounds | asio::ssl::context::no_sslv2 |
                       asio::ssl::context::no_sslv3 | asio::ssl::context::no_tlsv1 |
                       asio::ssl::context::no_tlsv1_1 | asio::ssl::context::single_dh_use);
  boost::system::error_code ec;
  context->use_certificate_chain_file(o.tls_cert, ec);
  if (!ec) context->use_private_key_file(o.tls_key, asio::ssl::context::pem, ec);
  if (ec || SSL_CTX_check_private_key(context->native_handle()) != 1) {
    throw std::invalid_argument("TLS certificate '" + o.tls_cert + "' and key '" + o.tls_key +
                                "': not a PEM certificate chain and its matching private key");
  }
  return context;
}

/// The options, with max_connections no more than the process's open-file limit leaves beside
/// the files the rest of the program holds (DDS sockets, run files).
ServerOptions within_file_limit(ServerOptions o) {
  constexpr rlim_t reserved = 128;
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur != RLIM_INFINITY) {
    const auto room = files.rlim_cur > 2 * reserved ? files.rlim_cur - reserved : files.rlim_cur / 2;
    o.max_connections = std::min<std::size_t>(o.max_connections, static_cast<std::size_t>(room));
  }
  return o;
}

/// One state event's bytes, made once and written to every stream.
struct Event {
  std::uint64_t version = 0;
  std::string text;
};

/// A connection as the server sees it from outside its strand.
class Connection {
 public:
  virtual ~Connection() = default;
  /// Closes the socket (any thread); whatever it was doing ends.
  virtual void close() = 0;
  /// For an event stream: the newest event, and whether a keep-alive or the stream's end is due.
  virtual void offer(std::shared_ptr<const Event> event, Clock::time_point now) = 0;
  /// Under the server's mutex: it is being evicted. Its entry in its peer's waiting list was
  /// erased, and it no longer counts towards its address's cap (its close is on its way).
  virtual void evicted() = 0;
};

/// What the server keeps of one client address.
struct Peer {
  std::size_t connections = 0;
  /// Its connections waiting for a request, oldest first: the ones a new connection from the
  /// same address evicts when the address holds its cap.
  std::list<std::weak_ptr<Connection>> waiting;
};

}  // namespace

bool is_run_file(const std::string& name) {
  for (const char* f : run_files) {
    if (name == f) return true;
  }
  return false;
}

struct Server::Impl {
  LiveState& state;
  ServerOptions options;
  std::unordered_map<std::string, Handler> get_routes;
  std::unordered_map<std::string, Handler> post_routes;

  std::atomic<bool> stopping{false};
  std::atomic<bool> bound{false};
  std::array<std::atomic<std::uint64_t>, 6> responses{};
  std::atomic<std::size_t> event_streams{0};
  std::atomic<std::size_t> queued{0};
  std::atomic<std::uint64_t> refused{0};
  std::atomic<std::uint64_t> evicted{0};
  std::atomic<std::uint64_t> failures{0};  ///< handlers that threw (the first said on stderr)

  mutable std::mutex mutex;  ///< guards what follows
  std::list<std::weak_ptr<Connection>> connections;
  std::list<std::weak_ptr<Connection>> streams;
  std::unordered_map<std::string, Peer> peers;
  std::shared_ptr<const Event> event;

  // Destroyed in reverse: the workers joined first, then the loop's objects, then the loop
  // (whose pending handlers hold connections, which unregister above), then the TLS context.
  std::unique_ptr<asio::ssl::context> tls;
  asio::io_context loop;
  asio::strand<asio::io_context::executor_type> control{asio::make_strand(loop)};
  tcp::acceptor acceptor{control};
  asio::steady_timer ticker{control};
  asio::steady_timer accept_pause{control};
  asio::thread_pool workers;

  Impl(LiveState& s, ServerOptions o)
      : state(s),
        options(within_file_limit(std::move(o))),
        tls(tls_context(options)),
        loop(static_cast<int>(std::max<std::size_t>(options.io_threads, 1))),
        workers(std::max<std::size_t>(options.workers, 1)) {}

  void routes();
  void page_routes();
  void state_routes();
  void replay_route();
  void run_file_routes();
  bool authorized(const Request& req, Response& res) const;
  /// Routes @p req; fills @p res (or its on_worker).
  void respond(const http::request<http::string_body>& req, Response& res);

  void accept();
  void admit(tcp::socket socket);
  void broadcast();
  std::int64_t beat = 0;  ///< broadcast()'s count, on the control strand
  std::shared_ptr<const Event> current_event();
  void count(unsigned status) {
    const auto cls = status / 100;
    if (cls >= 1 && cls <= 5) ++responses[cls];
  }
  void stop();
};

namespace {

/// One client connection on its own strand: reads requests and answers them, or, once it asked
/// for /api/events, writes the events it is offered. Stream is beast::tcp_stream or its TLS
/// stream.
template <class Stream>
class Session : public Connection, public std::enable_shared_from_this<Session<Stream>> {
 public:
  static constexpr bool tls = !std::is_same_v<Stream, beast::tcp_stream>;

  template <class... StreamArgs>
  Session(Server::Impl& server, std::string address, StreamArgs&&... stream_args)
      : server_(server), address_(std::move(address)), stream_(std::forward<StreamArgs>(stream_args)...),
        buffer_(server.options.max_payload + max_header) {}

  ~Session() override {
    std::lock_guard lock(server_.mutex);
    server_.connections.erase(registration_);
    if (streaming_) {
      server_.streams.erase(stream_registration_);
    }
    if (stream_reserved_) --server_.event_streams;
    const auto peer = server_.peers.find(address_);
    if (peer == server_.peers.end()) return;  // evicted, and the address's last one
    if (waiting_at_) peer->second.waiting.erase(*waiting_at_);
    if (counted_ && --peer->second.connections == 0) server_.peers.erase(peer);
  }

  /// Called once, under the server's mutex, right after construction: its places in the
  /// server's list and, waiting for its first request from the start, in its peer's.
  void registered(std::list<std::weak_ptr<Connection>>::iterator at,
                  std::list<std::weak_ptr<Connection>>::iterator waiting_at) {
    registration_ = at;
    waiting_at_ = waiting_at;
  }

  void start() {
    asio::dispatch(stream_.get_executor(), [self = this->shared_from_this()] {
      if constexpr (tls) {
        self->lowest().expires_after(self->server_.options.read_timeout);
        self->stream_.async_handshake(asio::ssl::stream_base::server,
                                      [self](beast::error_code ec) {
                                        if (ec) return self->drop();
                                        self->read();
                                      });
      } else {
        self->read();
      }
    });
  }

  void evicted() override {
    waiting_at_.reset();
    counted_ = false;
  }

  void close() override {
    asio::post(stream_.get_executor(), [self = this->shared_from_this()] { self->drop(); });
  }

  void offer(std::shared_ptr<const Event> event, Clock::time_point now) override {
    asio::post(stream_.get_executor(), [self = this->shared_from_this(), event = std::move(event), now] {
      if (!self->streaming_ || self->dropped_) return;
      const auto& o = self->server_.options;
      if (event && event->version != self->seen_) self->pending_ = event;
      if (self->server_.stopping.load() || now - self->opened_ > o.event_stream_lifetime) {
        self->finishing_ = true;
      } else if (!self->pending_ && now - self->last_sent_ > o.event_keep_alive) {
        self->comment_due_ = true;
      }
      self->write_next();
    });
  }

 private:
  beast::tcp_stream& lowest() { return beast::get_lowest_layer(stream_); }

  /// Lists or unlists this connection as waiting for a request (evictable), under the mutex.
  void waiting(bool yes) {
    std::lock_guard lock(server_.mutex);
    if (!counted_) return;  // evicted: its close is on its way
    auto& list = server_.peers[address_].waiting;
    if (yes && !waiting_at_) {
      waiting_at_ = list.insert(list.end(), this->weak_from_this());
    } else if (!yes && waiting_at_) {
      list.erase(*waiting_at_);
      waiting_at_.reset();
    }
  }

  void read() {
    if (server_.stopping.load()) return drop();
    waiting(true);
    parser_.emplace();
    parser_->header_limit(max_header);
    parser_->body_limit(server_.options.max_payload);
    lowest().expires_after(server_.options.read_timeout);
    http::async_read_header(stream_, buffer_, *parser_,
                            [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                              self->waiting(false);
                              if (ec) return self->failed(ec);
                              if (self->parser_->is_done()) return self->handle();
                              // The body has a deadline of its own.
                              self->lowest().expires_after(self->server_.options.read_timeout);
                              http::async_read(self->stream_, self->buffer_, *self->parser_,
                                               [self](beast::error_code ec2, std::size_t) {
                                                 if (ec2) return self->failed(ec2);
                                                 self->handle();
                                               });
                            });
  }

  /// A request that could not be read: answered when it was malformed or too large, else
  /// dropped (the client left, or stalled past its deadline).
  void failed(beast::error_code ec) {
    if (ec == http::error::header_limit || ec == http::error::buffer_overflow) {
      return answer_error(request_line_too_long() ? 414 : 431);
    }
    if (ec == http::error::body_limit) return answer_error(413);
    if (ec.category() == beast::http::make_error_code(http::error::bad_method).category() &&
        ec != http::error::end_of_stream && ec != http::error::partial_message) {
      return answer_error(400);
    }
    drop();
  }

  /// Whether the bytes read so far hold no line end within the first 8 KiB.
  bool request_line_too_long() const {
    const auto data = buffer_.data();
    const std::string_view seen(static_cast<const char*>(data.data()), std::min(data.size(), max_request_line + 2));
    return seen.find("\r\n") == std::string_view::npos;
  }

  void answer_error(unsigned status) {
    Response res;
    res.error(status, std::to_string(status) + " " + reason(status));
    write(std::move(res), false, 11, false);
  }

  void handle() {
    auto req = parser_->release();
    // HTTP/1.0 is answered in kind; 1.1 and any later 1.x as 1.1 (RFC 9110 §2.5); another major
    // version not at all.
    if (req.version() / 10 != 1) return answer_error(505);
    const unsigned version = req.version() == 10 ? 10 : 11;
    Response res;
    try {
      server_.respond(req, res);
      if (res.ranges && res.status == 200) {
        const auto range = req.find(http::field::range);
        if (range != req.end()) apply_range(range->value(), res);
      }
    } catch (const std::exception&) {
      if (res.event_stream) --server_.event_streams;  // reserved by the route
      res = Response();
      res.error(500, "500 internal error");
    }
    const bool head = req.method() == http::verb::head;
    const bool keep = req.keep_alive() && ++served_ < server_.options.max_requests_per_connection;
    if (res.event_stream) {
      stream_reserved_ = true;
      return begin_stream(version);
    }
    if (!res.on_worker) return write(std::move(res), head, version, keep);
    // A report: rendered on a worker, at most max_queued waiting.
    if (server_.queued.fetch_add(1) >= server_.options.max_queued) {
      --server_.queued;
      Response busy;
      busy.error(503, "503 busy: too many reports are being rendered; try again");
      busy.set("Retry-After", "2");
      return write(std::move(busy), head, version, keep);
    }
    auto work = asio::make_work_guard(stream_.get_executor());
    asio::post(server_.workers, [self = this->shared_from_this(), res = std::move(res), head,
                                 version, keep, work = std::move(work)]() mutable {
      auto job = std::move(res.on_worker);
      try {
        job(res);
      } catch (const std::exception&) {
        res = Response();
        res.error(500, "500 internal error");
      }
      --self->server_.queued;
      asio::post(self->stream_.get_executor(), [self, res = std::move(res), head, version, keep]() mutable {
        self->write(std::move(res), head, version, keep);
      });
    });
  }

  /// Writes @p res; then reads the next request on a kept-alive connection, or closes.
  void write(Response res, bool head, unsigned version, bool keep) {
    if (dropped_) return;
    keep = keep && !server_.stopping.load();
    std::uint64_t head_size = 0;  // for HEAD: the length the body would have
    if (!res.file.empty()) {
      http::file_body::value_type file;
      beast::error_code ec;
      file.open(res.file.c_str(), beast::file_mode::scan, ec);
      if (!ec && !head) {
        http::response<http::file_body> message{static_cast<http::status>(res.status), version};
        fill(message, res, keep);
        message.body() = std::move(file);
        message.prepare_payload();
        return send(std::make_shared<decltype(message)>(std::move(message)), res.status, keep);
      }
      if (ec) {
        const auto name = std::filesystem::path(res.file).filename().string();
        res = Response();
        res.error(404, "404 " + name + " is not in the run directory (yet)");
      } else {
        res.body.clear();
        head_size = file.size();
      }
    } else if (head) {
      head_size = res.body.size();
      res.body.clear();
    }
    http::response<http::string_body> message{static_cast<http::status>(res.status), version};
    fill(message, res, keep);
    message.body() = std::move(res.body);
    if (head) {
      message.content_length(head_size);
    } else {
      message.prepare_payload();
    }
    send(std::make_shared<decltype(message)>(std::move(message)), res.status, keep);
  }

  template <class Message>
  void fill(Message& message, const Response& res, bool keep) {
    message.set(http::field::server, "retreat-bridge");
    message.set("X-Content-Type-Options", "nosniff");
    if (!res.content_type.empty()) message.set(http::field::content_type, res.content_type);
    for (const auto& [name, value] : res.headers) message.insert(name, value);
    if (res.ranges) message.set(http::field::accept_ranges, "bytes");
    message.keep_alive(keep);
  }

  template <class Message>
  void send(std::shared_ptr<Message> message, unsigned status, bool keep) {
    server_.count(status);
    lowest().expires_after(server_.options.write_timeout);
    http::async_write(stream_, *message,
                      [self = this->shared_from_this(), message, keep](beast::error_code ec, std::size_t) {
                        if (ec) return self->drop();
                        if (keep) return self->read();
                        self->finish();
                      });
  }

  /// After the last response: stop sending, then read (and discard) whatever the client still
  /// sends for a moment, so that closing does not reset the connection before the client has
  /// read the answer (a request refused for its size may still be arriving).
  void finish() {
    if constexpr (tls) {
      lowest().expires_after(server_.options.read_timeout);
      stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) { self->drop(); });
    } else {
      beast::error_code ec;
      lowest().socket().shutdown(tcp::socket::shutdown_send, ec);
      if (ec) return drop();
      lowest().expires_after(std::min<std::chrono::milliseconds>(server_.options.read_timeout, 1000ms));
      discard(lowest(), 4 * server_.options.max_payload);
    }
  }

  /// Reads and throws away what the client sends on @p layer (the TCP stream, or the stream
  /// itself) until it closes, fails, or has sent more than @p limit bytes; then drops the
  /// connection. After the last answer (finish) and for an event stream's life (begin_stream).
  template <class Layer>
  void discard(Layer& layer, std::size_t limit) {
    layer.async_read_some(asio::buffer(scratch_), [self = this->shared_from_this(), &layer, limit](beast::error_code ec, std::size_t n) {
      self->drained_ += n;
      if (ec || self->drained_ > limit) return self->drop();
      self->discard(layer, limit);
    });
  }

  void drop() {
    if (dropped_) return;
    dropped_ = true;
    beast::error_code ec;
    lowest().socket().shutdown(tcp::socket::shutdown_both, ec);
    lowest().close();
  }

  /// /api/events: the response's head, `retry:`, the current state, then what offer() brings.
  void begin_stream(unsigned version) {
    {
      std::lock_guard lock(server_.mutex);
      streaming_ = true;
      stream_registration_ = server_.streams.insert(server_.streams.end(), this->weak_from_this());
    }
    if (server_.stopping.load()) return drop();
    server_.count(200);
    opened_ = last_sent_ = Clock::now();
    pending_ = server_.current_event();
    stream_head_.emplace(http::status::ok, version);
    stream_head_->set(http::field::server, "retreat-bridge");
    stream_head_->set(http::field::content_type, "text/event-stream");
    stream_head_->set(http::field::cache_control, "no-store");
    stream_head_->set("X-Accel-Buffering", "no");
    stream_head_->set("X-Content-Type-Options", "nosniff");
    stream_head_->chunked(true);
    stream_head_->keep_alive(true);
    head_serializer_.emplace(*stream_head_);
    // A read stays pending for the stream's life, with no deadline: it keeps the session alive
    // between events and ends it when the client leaves. Deadlines set while it is pending are
    // the writes' only.
    lowest().expires_never();
    discard(stream_, server_.options.max_payload);  // nothing, normally
    writing_ = true;
    lowest().expires_after(server_.options.write_timeout);
    http::async_write_header(stream_, *head_serializer_,
                             [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                               self->writing_ = false;
                               if (ec) return self->drop();
                               self->write_next();
                             });
  }

  /// Writes the next chunk due, if none is being written: the greeting, the newest event
  /// (replacing any older one not yet written), a keep-alive comment, or the stream's end.
  void write_next() {
    if (writing_ || dropped_) return;
    static const auto greeting = std::make_shared<const std::string>("retry: 1000\n\n");
    static const auto comment = std::make_shared<const std::string>(": idle\n\n");
    std::shared_ptr<const void> keep;
    asio::const_buffer bytes;
    if (!greeted_) {
      greeted_ = true;
      keep = greeting;
      bytes = asio::buffer(*greeting);
    } else if (pending_) {
      seen_ = pending_->version;
      bytes = asio::buffer(pending_->text);
      keep = std::move(pending_);
      pending_.reset();
    } else if (comment_due_) {
      comment_due_ = false;
      keep = comment;
      bytes = asio::buffer(*comment);
    } else if (finishing_) {
      writing_ = true;
      lowest().expires_after(server_.options.write_timeout);
      asio::async_write(stream_, http::make_chunk_last(),
                        [self = this->shared_from_this()](beast::error_code ec, std::size_t) {
                          if (ec) return self->drop();
                          self->finish();
                        });
      return;
    } else {
      return;
    }
    writing_ = true;
    last_sent_ = Clock::now();
    lowest().expires_after(server_.options.write_timeout);
    asio::async_write(stream_, http::make_chunk(bytes),
                      [self = this->shared_from_this(), keep](beast::error_code ec, std::size_t) {
                        self->writing_ = false;
                        if (ec) return self->drop();
                        self->write_next();
                      });
  }

  Server::Impl& server_;
  std::string address_;
  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::list<std::weak_ptr<Connection>>::iterator registration_;
  /// Its entry in its peer's waiting list, and whether it counts towards its address's cap (not
  /// once evicted); guarded by the server's mutex.
  std::optional<std::list<std::weak_ptr<Connection>>::iterator> waiting_at_;
  bool counted_ = true;
  std::size_t served_ = 0;
  bool dropped_ = false;
  std::array<char, 4096> scratch_{};
  std::size_t drained_ = 0;

  // An event stream.
  bool stream_reserved_ = false;
  bool streaming_ = false;
  std::list<std::weak_ptr<Connection>>::iterator stream_registration_;
  std::optional<http::response<http::empty_body>> stream_head_;
  std::optional<http::response_serializer<http::empty_body>> head_serializer_;
  bool writing_ = false;
  bool greeted_ = false;
  bool comment_due_ = false;
  bool finishing_ = false;
  std::shared_ptr<const Event> pending_;
  std::uint64_t seen_ = ~std::uint64_t{0};
  Clock::time_point opened_{};
  Clock::time_point last_sent_{};
};

}  // namespace

// ---- routes ---------------------------------------------------------------------------------

void Server::Impl::routes() {
  page_routes();
  state_routes();
  replay_route();
  run_file_routes();
}

/// The dashboard's page and its assets, embedded in the program.
void Server::Impl::page_routes() {
  const auto asset = [](const std::string& name) {
    return [name](const Request&, Response& res) {
      const auto* a = report::find_web_asset(name);
      if (a == nullptr) return res.error(404, "404 not found");
      res.content(std::string(a->data), std::string(report::content_type_for(name)));
      res.ranges = true;
      res.set("Cache-Control", name == "index.html" ? "no-cache" : "max-age=300");
      if (name == "index.html") {
        res.set("Content-Security-Policy",
                "default-src 'self'; img-src 'self' data:; style-src 'self' 'unsafe-inline'");
      }
    };
  };
  get_routes["/"] = asset("index.html");
  get_routes["/index.html"] = asset("index.html");
  for (const auto& a : report::web_assets()) {
    const std::string name(a.name);
    if (name == "index.html" || name.rfind("report", 0) == 0) continue;  // report.* are for files
    get_routes["/" + name] = asset(name);
  }
}

/// The JSON API, the event stream and the Prometheus metrics.
void Server::Impl::state_routes() {
  get_routes["/api/state"] = [this](const Request&, Response& res) {
    res.no_store();
    res.content(state.state_text().first, json_type);
  };
  get_routes["/api/history"] = [this](const Request&, Response& res) {
    res.no_store();
    res.content(state.history_text(), json_type);
  };
  get_routes["/metrics"] = [this](const Request&, Response& res) {
    res.no_store();
    res.content(state.metrics_text([this](telemetry::PrometheusWriter& out) {
      if (options.extra_metrics) options.extra_metrics(out);
    }),
                telemetry::prometheus_content_type);
  };
  get_routes["/api/events"] = [this](const Request& req, Response& res) {
    if (req.method == http::verb::head) return res.error(405, "405 /api/events is a stream: GET it");
    if (event_streams.fetch_add(1) >= options.max_event_streams) {
      --event_streams;
      res.set("Retry-After", "5");
      return res.error(503, "503 too many event streams (" + std::to_string(options.max_event_streams) + ")");
    }
    res.event_stream = true;
  };
}

/// /api/replay (retreat-bridge --replay): the position in the recording, and moving it.
///   GET  /api/replay                      {replaying: true, first_tick, last_tick, first_time,
///                                          last_time, tick, time, playing, speed}; a live bridge
///                                          {replaying: false}, and 409 to a POST
///   POST /api/replay?tick=N               seek (and pause)
///   POST /api/replay?play=1[&speed=S]     play at S simulated s per wall s (default 1)
///   POST /api/replay?play=0               pause
/// A bad parameter gets 400 with one line naming it and what is allowed.
void Server::Impl::replay_route() {
  const auto position_json = [](const ReplayPosition& p) {
    return nlohmann::json{{"replaying", true},        {"first_tick", p.first_tick}, {"last_tick", p.last_tick},
                          {"first_time", p.first_time}, {"last_time", p.last_time},   {"tick", p.tick},
                          {"time", p.time},           {"playing", p.playing},       {"speed", p.speed}}
        .dump();
  };
  get_routes["/api/replay"] = [this, position_json](const Request&, Response& res) {
    res.no_store();
    if (options.replay == nullptr) return res.content(R"({"replaying":false})", json_type);
    res.content(position_json(options.replay->position()), json_type);
  };
  post_routes["/api/replay"] = [this, position_json](const Request& req, Response& res) {
    auto* player = options.replay;
    if (player == nullptr) return res.error(409, "409 not replaying a recording (retreat-bridge --replay FILE)");
    for (const auto& [key, value] : req.query) {
      if (key != "tick" && key != "play" && key != "speed") {
        return res.error(400, "400 unknown parameter '" + key.substr(0, 64) + "': tick, play or speed");
      }
    }
    const auto number = [&](const std::string& key, double& out) {
      const auto value = req.param(key);
      const char* first = value.data();
      const auto [end, ec] = std::from_chars(first, first + value.size(), out);
      return ec == std::errc() && end == first + value.size() && std::isfinite(out);
    };
    if (req.has("tick")) {
      double tick = 0;
      if (!number("tick", tick) || tick != std::floor(tick) || std::abs(tick) > 9e15) {
        return res.error(400, "400 tick '" + req.param("tick").substr(0, 64) + "': a whole number");
      }
      player->seek(static_cast<std::int64_t>(tick));
    }
    if (req.has("play")) {
      const auto play = req.param("play");
      double speed = 1.0;
      if (req.has("speed") && (!number("speed", speed) || speed <= 0.0 || speed > ReplayPlayer::max_speed)) {
        return res.error(400, "400 speed '" + req.param("speed").substr(0, 64) + "': more than 0 and at most " +
                                  std::to_string(static_cast<int>(ReplayPlayer::max_speed)));
      }
      if (play == "1") {
        player->play(speed);
      } else if (play == "0") {
        player->pause();
      } else {
        return res.error(400, "400 play '" + play.substr(0, 64) + "': 1 or 0");
      }
    } else if (req.has("speed")) {
      return res.error(400, "400 speed without play=1");
    }
    res.no_store();
    res.content(position_json(player->position()), json_type);
  };
}

/// The run directory: /api/runs lists its files, /runs/<file> serves one, /report renders one.
void Server::Impl::run_file_routes() {
  get_routes["/api/runs"] = [this](const Request&, Response& res) {
    res.no_store();
    nlohmann::json j;
    j["files"] = nlohmann::json::array();
    if (!options.run_dir.empty()) {
      for (const char* f : run_files) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(options.run_dir + "/" + f, ec);
        if (!ec) j["files"].push_back({{"name", f}, {"size", size}, {"url", std::string("/runs/") + f}});
      }
    }
    j["recording"] = !options.run_dir.empty();
    res.content(j.dump(), json_type);
  };
  get_routes["/report"] = [this](const Request&, Response& res) {
    if (options.run_dir.empty()) return res.error(404, "404 no run directory (start with --out DIR)");
    res.on_worker = [dir = options.run_dir](Response& out) {
      out.no_store();
      try {
        out.content(report::render_report(dir), "text/html; charset=utf-8");
      } catch (const std::exception& e) {
        out.error(409, std::string("409 no report yet: ") + e.what());
      }
    };
  };
}

bool Server::Impl::authorized(const Request& req, Response& res) const {
  const auto& token = options.token;
  if (token.empty()) return true;
  const auto refuse = [&res] {
    res.set("WWW-Authenticate", "Bearer realm=\"retreat-bridge\"");
    res.error(401, "401 a token is required: Authorization: Bearer TOKEN, or open /?token=TOKEN");
    return false;
  };
  if (req.has("token") && req.method == http::verb::get && (req.path == "/" || req.path == "/index.html")) {
    if (!same_secret(req.param("token"), token)) return refuse();
    res.status = 303;
    res.set("Location", req.path);
    res.set("Set-Cookie", std::string(token_cookie) + "=" + token + "; Path=/; HttpOnly; SameSite=Strict" +
                              (tls ? "; Secure" : ""));
    res.no_store();
    return false;
  }
  constexpr std::string_view bearer = "Bearer ";
  const auto authorization = req.header(http::field::authorization);
  const bool by_header = authorization.size() > bearer.size() && authorization.compare(0, bearer.size(), bearer) == 0 &&
                         same_secret(std::string_view(authorization).substr(bearer.size()), token);
  if (by_header || same_secret(cookie(req.header(http::field::cookie), token_cookie), token)) return true;
  return refuse();
}

void Server::Impl::respond(const http::request<http::string_body>& message, Response& res) {
  Request req{message.method(), {}, {}, message.base()};
  if (!parse_target(message.target(), req.path, req.query) || req.path.empty() || req.path.front() != '/') {
    return res.error(400, "400 the request target is not a path with a well-formed query");
  }
  if (!authorized(req, res)) return;
  const bool reading = req.method == http::verb::get || req.method == http::verb::head;
  if (reading) {
    if (const auto it = get_routes.find(req.path); it != get_routes.end()) return it->second(req, res);
    constexpr std::string_view runs = "/runs/";
    if (req.path.compare(0, runs.size(), runs) == 0) {
      const auto name = req.path.substr(runs.size());
      if (options.run_dir.empty()) return res.error(404, "404 no run directory (start with --out DIR)");
      if (!is_run_file(name)) return res.error(404, "404 not a run file");
      res.no_store();
      if (name != "report.html") res.set("Content-Disposition", "attachment; filename=\"" + name + "\"");
      res.content_type = std::string(report::content_type_for(name));
      res.file = options.run_dir + "/" + name;  // the arena may still be appending: its size now
      return;
    }
  } else if (req.method == http::verb::post) {
    if (const auto it = post_routes.find(req.path); it != post_routes.end()) return it->second(req, res);
  }
  const bool known = get_routes.count(req.path) != 0 || post_routes.count(req.path) != 0;
  if (!known || reading) return res.error(404, "404 not found");
  std::string allow = get_routes.count(req.path) != 0 ? "GET, HEAD" : "";
  if (post_routes.count(req.path) != 0) allow += allow.empty() ? "POST" : ", POST";
  res.set("Allow", allow);
  res.error(405, "405 method not allowed: " + allow);
}

// ---- connections ----------------------------------------------------------------------------

void Server::Impl::accept() {
  acceptor.async_accept(asio::make_strand(loop), [this](beast::error_code ec, tcp::socket socket) {
    if (!acceptor.is_open() || ec == asio::error::operation_aborted) return;
    if (!ec) {
      admit(std::move(socket));
      return accept();
    }
    // Out of file descriptors, most likely: try again shortly instead of spinning.
    accept_pause.expires_after(50ms);
    accept_pause.async_wait([this](beast::error_code wait) {
      if (!wait) accept();
    });
  });
}

void Server::Impl::admit(tcp::socket socket) {
  beast::error_code ec;
  const auto remote = socket.remote_endpoint(ec);
  if (ec) return;
  const auto address = remote.address().to_string();
  socket.set_option(tcp::no_delay(true), ec);
  std::unique_lock lock(mutex);
  auto& peer = peers[address];
  // An address at its cap makes room by evicting its oldest connection that waits for a
  // request (a stalled or idle one); if all of its connections are busy, it is refused.
  std::shared_ptr<Connection> evict;
  if (peer.connections >= options.max_connections_per_address) {
    for (auto it = peer.waiting.begin(); it != peer.waiting.end(); ++it) {
      if ((evict = it->lock())) {
        peer.waiting.erase(it);
        evict->evicted();
        --peer.connections;
        break;
      }
    }
  }
  if (stopping.load() || connections.size() >= options.max_connections ||
      (peer.connections >= options.max_connections_per_address && !evict)) {
    if (peer.connections == 0) peers.erase(address);
    lock.unlock();
    ++refused;
    if (!tls && !stopping.load()) {
      // One best-effort write on the fresh socket (its send buffer is empty), then close.
      const std::string body = "503 too many connections from " + address + "; try again\n";
      const std::string answer = "HTTP/1.1 503 Service Unavailable\r\nRetry-After: 2\r\nConnection: close\r\n"
                                 "Content-Type: text/plain; charset=utf-8\r\nContent-Length: " +
                                 std::to_string(body.size()) + "\r\n\r\n" + body;
      socket.non_blocking(true, ec);
      socket.write_some(asio::buffer(answer), ec);
      count(503);
    }
    socket.shutdown(tcp::socket::shutdown_both, ec);
    socket.close(ec);
    return;
  }
  if (evict) {
    ++evicted;
    evict->close();
  }
  ++peer.connections;
  const auto start = [&](auto session) {
    session->registered(connections.insert(connections.end(), session), peer.waiting.insert(peer.waiting.end(), session));
    lock.unlock();
    session->start();
  };
  if (tls) {
    start(std::make_shared<Session<beast::ssl_stream<beast::tcp_stream>>>(*this, address, std::move(socket), *tls));
  } else {
    start(std::make_shared<Session<beast::tcp_stream>>(*this, address, std::move(socket)));
  }
}

std::shared_ptr<const Event> Server::Impl::current_event() {
  const auto version = state.version();
  {
    std::lock_guard lock(mutex);
    if (event && event->version == version) return event;
  }
  // Rendered outside the mutex, which every connection's start and end take.
  auto [text, rendered] = state.state_text();
  auto fresh = std::make_shared<Event>();
  fresh->version = rendered;
  fresh->text = "event: state\nid: " + std::to_string(rendered) + "\ndata: " + text + "\n\n";
  // The version can go back (a replay seeks back): the newest rendering is kept. If two
  // renderings race, the broadcaster's next look at the version corrects the loser.
  std::lock_guard lock(mutex);
  event = std::move(fresh);
  return event;
}

/// Every event_min_interval on the control strand: a changed state made into one event and
/// offered to every stream; once a second (housekeeping) every stream is offered the chance to
/// send a keep-alive comment or to end.
void Server::Impl::broadcast() {
  if (stopping.load()) return;
  const auto period = std::max<std::chrono::milliseconds>(options.event_min_interval, 1ms);
  const bool housekeeping = ++beat % std::max<std::int64_t>(1, 1000 / period.count()) == 0;
  const auto version = state.version();
  bool changed = false;
  std::vector<std::shared_ptr<Connection>> live;
  {
    std::lock_guard lock(mutex);
    changed = !event || event->version != version;
    if (changed || housekeeping) {
      live.reserve(streams.size());
      for (const auto& weak : streams) {
        if (auto s = weak.lock()) live.push_back(std::move(s));
      }
    }
  }
  if (!live.empty()) {
    const auto fresh = changed ? current_event() : nullptr;
    const auto now = Clock::now();
    for (const auto& s : live) s->offer(fresh, now);
  }
  ticker.expires_after(period);
  ticker.async_wait([this](beast::error_code ec) {
    if (!ec) broadcast();
  });
}

void Server::Impl::stop() {
  std::vector<std::shared_ptr<Connection>> open;
  {
    std::lock_guard lock(mutex);
    stopping.store(true);
    for (const auto& weak : connections) {
      if (auto c = weak.lock()) open.push_back(std::move(c));
    }
  }
  asio::post(control, [this] {
    beast::error_code ec;
    acceptor.close(ec);
    ticker.cancel();
    accept_pause.cancel();
  });
  for (const auto& c : open) c->close();
}

// ---- Server ---------------------------------------------------------------------------------

Server::Server(LiveState& state, ServerOptions options)
    : impl_(std::make_shared<Impl>(state, std::move(options))) {
  impl_->routes();
}

Server::~Server() { stop(); }

int Server::bind(const HttpAddress& address) {
  auto& acceptor = impl_->acceptor;
  const auto fail = [&](const std::string& why) {
    return std::runtime_error(address.host + ":" + std::to_string(address.port) + ": " + why);
  };
  beast::error_code ec;
  const auto host = asio::ip::make_address_v4(address.host, ec);  // parse_http_address checked it
  if (ec) throw fail("not an IPv4 address: " + ec.message());
  const tcp::endpoint endpoint(host, static_cast<std::uint16_t>(address.port));
  acceptor.open(endpoint.protocol(), ec);
  // SO_REUSEADDR only: with SO_REUSEPORT a second server would bind a port in use.
  if (!ec) acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) {
    acceptor.close();
    throw fail(ec.message());
  }
  impl_->bound.store(true);
  return acceptor.local_endpoint().port();
}

void Server::serve() {
  auto& impl = *impl_;
  if (!impl.bound.load()) throw std::logic_error("Server::serve() before bind()");
  if (impl.stopping.load()) return;
  asio::dispatch(impl.control, [&impl] {
    impl.accept();
    impl.broadcast();
  });
  // A handler that throws ends run() on its thread: said once, and that thread runs on (the
  // connection it served is dropped with the handler).
  const auto run = [&impl] {
    for (;;) {
      try {
        impl.loop.run();
        return;
      } catch (const std::exception& e) {
        if (impl.failures.fetch_add(1) == 0) std::fprintf(stderr, "retreat-bridge: an HTTP handler failed: %s\n", e.what());
      }
    }
  };
  std::vector<std::thread> more;
  for (std::size_t i = 1; i < impl.options.io_threads; ++i) more.emplace_back(run);
  run();
  for (auto& t : more) t.join();
}

void Server::stop() { impl_->stop(); }

std::array<std::uint64_t, 6> Server::responses() const {
  std::array<std::uint64_t, 6> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = impl_->responses[i].load();
  return out;
}

std::size_t Server::event_streams() const { return impl_->event_streams.load(); }

std::size_t Server::connections() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->connections.size();
}

std::uint64_t Server::connections_refused() const { return impl_->refused.load(); }

std::uint64_t Server::connections_evicted() const { return impl_->evicted.load(); }

std::uint64_t Server::handler_failures() const { return impl_->failures.load(); }

}  // namespace retreat::bridge
