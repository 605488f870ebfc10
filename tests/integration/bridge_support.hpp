#pragma once
/// @file
/// Helpers of the retreat-bridge integration tests: starting the program and reading its URL,
/// HTTP on 127.0.0.1 (with httplib, and raw sockets for malformed requests), and a headless
/// Chromium driven over its DevTools protocol on a pipe (--remote-debugging-pipe: no port, no
/// network), started and stopped by PID.

#include <sys/types.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "retreat/testing/process.hpp"

namespace retreat::testing::bridge {

/// Where tests leave files for people (screenshots): RETREAT_TEST_OUTPUT_DIR, created.
std::string output_dir();

/// A running retreat-bridge and the URL it printed (`http://127.0.0.1:PORT/`, or https).
struct Bridge {
  std::optional<ChildProcess> process;
  std::string url;
  int port = 0;
  std::string log;
};

/// Starts retreat-bridge with `args` (after the program path) and waits up to `timeout` for its
/// `retreat-bridge: serving http://...` line; `url` stays empty if it never came.
Bridge start_bridge(const std::vector<std::string>& args, const std::string& log,
                    std::chrono::milliseconds timeout = testing::hang_ceiling);

/// GET on 127.0.0.1:port; nullopt when no answer. Returns status and body.
struct Reply {
  int status = 0;
  std::string body;
  std::string content_type;
};
std::optional<Reply> get(int port, const std::string& path, std::chrono::seconds timeout = std::chrono::seconds(5));

/// A TCP connection to 127.0.0.1:port from source address @p from (any 127.x.y.z; the kernel's
/// choice when null): the socket, or -1 when it could not connect.
int connect_to(int port, const char* from = nullptr);

/// Sends `bytes` on a fresh TCP connection to 127.0.0.1:port and returns the server's answer:
/// one complete response, or what came before it closed or `timeout` passed. `keep_open`: for
/// readability at call sites that stall on purpose (the connection is never half-closed).
std::string raw_exchange(int port, const std::string& bytes, std::chrono::milliseconds timeout,
                         bool keep_open = false);

/// The status code of an HTTP response's first line, or 0.
int status_of(const std::string& response);

/// Headless Chromium over the DevTools protocol on fds 3/4 (--remote-debugging-pipe).
class Browser {
 public:
  /// Starts /usr/bin/chromium (or $RETREAT_CHROMIUM) with a fresh profile in `profile_dir`,
  /// opens a page of `width` × `height` CSS pixels; `extra_args` are added to Chromium's
  /// command line. @throws std::runtime_error when it fails.
  Browser(const std::string& profile_dir, int width, int height, const std::string& log_path,
          const std::vector<std::string>& extra_args = {});
  ~Browser();
  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;

  /// True when a chromium binary exists.
  static bool available();

  /// Navigates the page and waits for its load event (up to `timeout`).
  void navigate(const std::string& url, std::chrono::milliseconds timeout = testing::hang_ceiling);
  /// Evaluates `expression` in the page; returns its value (JSON), null on failure.
  nlohmann::json evaluate(const std::string& expression);
  /// Saves a PNG screenshot of the viewport.
  void screenshot(const std::string& png_path);
  /// Script errors seen so far: uncaught exceptions, console.error, error log entries.
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  nlohmann::json call(const std::string& method, const nlohmann::json& params, bool in_session = true,
                      std::chrono::milliseconds timeout = testing::hang_ceiling);
  void read_messages(std::chrono::milliseconds timeout);
  void on_event(const nlohmann::json& message);
  pid_t pid_ = -1;
  int to_browser_ = -1;
  int from_browser_ = -1;
  std::string buffer_;
  std::vector<nlohmann::json> responses_;
  int next_id_ = 1;
  std::string session_;
  bool loaded_ = false;
  std::vector<std::string> errors_;
};

}  // namespace retreat::testing::bridge
