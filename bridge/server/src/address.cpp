#include "retreat/bridge/address.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
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

std::string probe_bind(const HttpAddress& address) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return std::strerror(errno);
  int yes = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_port = htons(static_cast<std::uint16_t>(address.port));
  inet_pton(AF_INET, address.host.c_str(), &sa.sin_addr);
  std::string why;
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) {
    why = std::strerror(errno);
  } else if (::listen(fd, 1) != 0) {
    why = std::strerror(errno);
  }
  ::close(fd);
  return why;
}

}  // namespace retreat::bridge
