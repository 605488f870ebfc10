#pragma once
/// @file
/// The `HOST:PORT` the bridge serves on (`--http`, `bridge.http`).

#include <string>

namespace retreat::bridge {

struct HttpAddress {
  std::string host;  ///< an IPv4 address (e.g. 127.0.0.1, 0.0.0.0) or `localhost`
  int port = 0;      ///< 0..65535; 0 picks a free port
};

/// Parses `HOST:PORT`. `what` names the value in the message (`--http` or `bridge.http`).
/// @throws std::invalid_argument with one line naming the value and what is allowed.
HttpAddress parse_http_address(const std::string& text, const std::string& what);

}  // namespace retreat::bridge
