#include "retreat/bridge/address.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <charconv>
#include <stdexcept>

namespace retreat::bridge {

HttpAddress parse_http_address(const std::string& text, const std::string& what) {
  const std::string allowed =
      ": must be HOST:PORT with HOST an IPv4 address or localhost and PORT in 0..65535 (0 picks a "
      "free port), e.g. 127.0.0.1:8080";
  const auto fail = [&] { return std::invalid_argument(what + " = '" + text + "'" + allowed); };
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) throw fail();
  HttpAddress a;
  a.host = text.substr(0, colon);
  const char* first = text.data() + colon + 1;
  const char* last = text.data() + text.size();
  unsigned port = 0;
  const auto [end, error] = std::from_chars(first, last, port);
  if (error != std::errc() || end != last || port > 65535) throw fail();
  a.port = static_cast<int>(port);
  if (a.host == "localhost") a.host = "127.0.0.1";
  in_addr parsed{};
  if (inet_pton(AF_INET, a.host.c_str(), &parsed) != 1) throw fail();
  return a;
}

}  // namespace retreat::bridge
