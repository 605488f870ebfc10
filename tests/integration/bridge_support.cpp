#include "bridge_support.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace retreat::testing::bridge {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

std::string output_dir() {
  const std::string dir = RETREAT_TEST_OUTPUT_DIR;
  fs::create_directories(dir);
  return dir;
}

Bridge start_bridge(const std::vector<std::string>& args, const std::string& log, std::chrono::milliseconds timeout) {
  Bridge b;
  b.log = log;
  std::vector<std::string> argv = {RETREAT_BRIDGE_BIN};
  argv.insert(argv.end(), args.begin(), args.end());
  b.process.emplace(argv, log);
  // "retreat-bridge: serving http://HOST:PORT/" or https, perhaps followed by a note.
  const std::string marker = "retreat-bridge: serving ";
  eventually(
      [&] {
        const auto text = read_file(log);
        const auto at = text.find(marker);
        if (at != std::string::npos) {
          const auto end = text.find_first_of(" \n", at + marker.size());
          if (end != std::string::npos) {
            b.url = text.substr(at + marker.size(), end - (at + marker.size()));
            const auto colon = b.url.rfind(':');
            b.port = std::stoi(b.url.substr(colon + 1));
            return true;
          }
        }
        return !b.process->running();
      },
      timeout);
  return b;
}

std::optional<Reply> get(int port, const std::string& path, std::chrono::seconds timeout) {
  httplib::Client c("127.0.0.1", port);
  c.set_connection_timeout(timeout);
  c.set_read_timeout(timeout);
  auto res = c.Get(path);
  if (!res) return std::nullopt;
  return Reply{res->status, res->body, res->get_header_value("Content-Type")};
}

int connect_to(int port, const char* from) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_in source{};
  source.sin_family = AF_INET;
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  if ((from != nullptr && (inet_pton(AF_INET, from, &source.sin_addr) != 1 ||
                           ::bind(fd, reinterpret_cast<const sockaddr*>(&source), sizeof source) != 0)) ||
      ::connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

std::string raw_exchange(int port, const std::string& bytes, std::chrono::milliseconds timeout, bool keep_open) {
  const int fd = connect_to(port);
  if (fd < 0) return {};
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const auto n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server may close early on an oversized request
    sent += static_cast<std::size_t>(n);
  }
  (void)keep_open;  // never half-closed: a stalled client, as the tests using it mean it, keeps sending
  std::string answer;
  // A complete response: headers, then Content-Length bytes (the server may keep the
  // connection open afterwards).
  const auto complete = [&answer] {
    const auto end = answer.find("\r\n\r\n");
    if (end == std::string::npos) return false;
    std::string head = answer.substr(0, end);
    for (auto& c : head) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const auto at = head.find("content-length:");
    if (at == std::string::npos) return true;
    const auto length = std::strtoull(head.c_str() + at + 15, nullptr, 10);
    return answer.size() >= end + 4 + length;
  };
  const auto deadline = Clock::now() + timeout;
  char buffer[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) break;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left)) <= 0) break;
    const auto n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    answer.append(buffer, static_cast<std::size_t>(n));
    if (complete()) break;
  }
  ::close(fd);
  return answer;
}

int status_of(const std::string& response) {
  if (response.rfind("HTTP/1.", 0) != 0 || response.size() < 12) return 0;
  return std::atoi(response.c_str() + 9);
}

// --- Browser ---------------------------------------------------------------------------------

namespace {

std::string chromium_path() {
  const char* env = std::getenv("RETREAT_CHROMIUM");
  return env != nullptr && *env != '\0' ? env : "/usr/bin/chromium";
}

std::string base64_decode(const std::string& in) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned value = 0;
  int bits = -8;
  for (char c : in) {
    const auto k = alphabet.find(c);
    if (k == std::string::npos) continue;  // '=' and line breaks
    value = (value << 6) | static_cast<unsigned>(k);
    bits += 6;
    if (bits >= 0) {
      out.push_back(static_cast<char>((value >> bits) & 0xFF));
      bits -= 8;
    }
  }
  return out;
}

}  // namespace

bool Browser::available() { return ::access(chromium_path().c_str(), X_OK) == 0; }

Browser::Browser(const std::string& profile_dir, int width, int height, const std::string& log_path,
                 const std::vector<std::string>& extra_args) {
  fs::remove_all(profile_dir);
  fs::create_directories(profile_dir);
  int to_child[2], from_child[2];
  if (::pipe2(to_child, O_CLOEXEC) != 0 || ::pipe2(from_child, O_CLOEXEC) != 0) {
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  }
  const std::string exe = chromium_path();
  std::vector<std::string> argv = {exe,
                                   "--headless",
                                   "--no-sandbox",
                                   "--disable-gpu",
                                   "--disable-quic",
                                   "--no-first-run",
                                   "--disable-background-networking",
                                   "--disable-component-update",
                                   "--disable-sync",
                                   "--disable-dev-shm-usage",
                                   "--user-data-dir=" + profile_dir,
                                   "--remote-debugging-pipe",
                                   "--window-size=" + std::to_string(width) + "," + std::to_string(height)};
  argv.insert(argv.end(), extra_args.begin(), extra_args.end());
  argv.emplace_back("about:blank");
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int devnull = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid_ == 0) {
    // Child: only async-signal-safe calls. Move the pipe ends above 4 first, then onto 3 and 4.
    const int in = ::fcntl(to_child[0], F_DUPFD, 10);
    const int out = ::fcntl(from_child[1], F_DUPFD, 10);
    ::dup2(devnull, 0);
    if (log >= 0) {
      ::dup2(log, 1);
      ::dup2(log, 2);
    }
    ::dup2(in, 3);
    ::dup2(out, 4);
    ::execv(exe.c_str(), args.data());
    ::_exit(127);
  }
  ::close(to_child[0]);
  ::close(from_child[1]);
  if (log >= 0) ::close(log);
  if (devnull >= 0) ::close(devnull);
  to_browser_ = to_child[1];
  from_browser_ = from_child[0];

  try {
    const auto target = call("Target.createTarget", {{"url", "about:blank"}}, false, retreat::testing::hang_ceiling);
    const auto attached = call("Target.attachToTarget", {{"targetId", target["targetId"]}, {"flatten", true}}, false);
    session_ = attached["sessionId"].get<std::string>();
    call("Runtime.enable", json::object());
    call("Page.enable", json::object());
    call("Log.enable", json::object());
    call("Emulation.setDeviceMetricsOverride",
         {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}});
  } catch (...) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    ::close(to_browser_);
    ::close(from_browser_);
    throw;
  }
}

Browser::~Browser() {
  if (pid_ > 0) {
    // Ask politely over the protocol, then by PID.
    try {
      call("Browser.close", json::object(), false, 3s);
    } catch (const std::exception&) {
    }
    int status = 0;
    bool gone = false;
    for (int i = 0; i < 100 && !gone; ++i) {
      gone = ::waitpid(pid_, &status, WNOHANG) == pid_;
      if (!gone) std::this_thread::sleep_for(20ms);
    }
    if (!gone) {
      ::kill(pid_, SIGTERM);
      for (int i = 0; i < 100 && !gone; ++i) {
        gone = ::waitpid(pid_, &status, WNOHANG) == pid_;
        if (!gone) std::this_thread::sleep_for(20ms);
      }
    }
    if (!gone) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
  }
  if (to_browser_ >= 0) ::close(to_browser_);
  if (from_browser_ >= 0) ::close(from_browser_);
}

void Browser::on_event(const json& m) {
  const auto method = m.value("method", std::string());
  const auto& p = m.contains("params") ? m["params"] : json::object();
  if (method == "Page.loadEventFired") {
    loaded_ = true;
  } else if (method == "Runtime.exceptionThrown") {
    const auto& d = p["exceptionDetails"];
    std::string text = d.value("text", std::string("exception"));
    if (d.contains("exception") && d["exception"].contains("description")) {
      text += ": " + d["exception"]["description"].get<std::string>();
    }
    errors_.push_back("uncaught " + text + " at " + d.value("url", std::string()) + ":" +
                      std::to_string(d.value("lineNumber", 0)));
  } else if (method == "Runtime.consoleAPICalled" && p.value("type", std::string()) == "error") {
    std::string text = "console.error:";
    for (const auto& a : p["args"]) text += " " + (a.contains("value") ? a["value"].dump() : a.value("description", std::string()));
    errors_.push_back(text);
  } else if (method == "Log.entryAdded" && p["entry"].value("level", std::string()) == "error") {
    errors_.push_back("log: " + p["entry"].value("text", std::string()) + " " + p["entry"].value("url", std::string()));
  }
}

void Browser::read_messages(std::chrono::milliseconds timeout) {
  pollfd p{from_browser_, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return;
  char chunk[65536];
  const auto n = ::read(from_browser_, chunk, sizeof chunk);
  if (n <= 0) throw std::runtime_error("chromium closed its DevTools pipe");
  buffer_.append(chunk, static_cast<std::size_t>(n));
  std::size_t end;
  while ((end = buffer_.find('\0')) != std::string::npos) {
    auto message = json::parse(buffer_.substr(0, end), nullptr, false);
    buffer_.erase(0, end + 1);
    if (message.is_discarded()) continue;
    if (message.contains("id")) {
      responses_.push_back(std::move(message));
    } else {
      on_event(message);
    }
  }
}

json Browser::call(const std::string& method, const json& params, bool in_session, std::chrono::milliseconds timeout) {
  const int id = next_id_++;
  json m = {{"id", id}, {"method", method}, {"params", params}};
  if (in_session) m["sessionId"] = session_;
  std::string text = m.dump();
  text.push_back('\0');
  std::size_t sent = 0;
  while (sent < text.size()) {
    const auto n = ::write(to_browser_, text.data() + sent, text.size() - sent);
    if (n <= 0) throw std::runtime_error("cannot write to chromium's DevTools pipe");
    sent += static_cast<std::size_t>(n);
  }
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    for (auto it = responses_.begin(); it != responses_.end(); ++it) {
      if ((*it)["id"] != id) continue;
      json r = std::move(*it);
      responses_.erase(it);
      if (r.contains("error")) throw std::runtime_error(method + ": " + r["error"].dump());
      return r.contains("result") ? r["result"] : json::object();
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) throw std::runtime_error(method + ": no answer from chromium");
    read_messages(std::min(left, std::chrono::milliseconds(100)));
  }
}

void Browser::navigate(const std::string& url, std::chrono::milliseconds timeout) {
  loaded_ = false;
  call("Page.navigate", {{"url", url}});
  const auto deadline = Clock::now() + timeout;
  while (!loaded_ && Clock::now() < deadline) read_messages(50ms);
  if (!loaded_) throw std::runtime_error("page did not load: " + url);
}

json Browser::evaluate(const std::string& expression) {
  const auto r = call("Runtime.evaluate", {{"expression", expression}, {"returnByValue", true}});
  // Events that arrived meanwhile are handled by call(); drain whatever else is waiting.
  read_messages(0ms);
  if (r.contains("exceptionDetails") || !r.contains("result")) return nullptr;
  return r["result"].value("value", json(nullptr));
}

void Browser::screenshot(const std::string& png_path) {
  const auto r = call("Page.captureScreenshot", {{"format", "png"}}, true, retreat::testing::hang_ceiling);
  std::ofstream(png_path, std::ios::binary) << base64_decode(r["data"].get<std::string>());
}

}  // namespace retreat::testing::bridge
