// --http / bridge.http: HOST:PORT with an IPv4 host (or localhost) and a port 0..65535.

#include "retreat/bridge/address.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace retreat::bridge {
namespace {

TEST(HttpAddress, ParsesHostAndPort) {
  const auto a = parse_http_address("127.0.0.1:8080", "--http");
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.port, 8080);
  EXPECT_EQ(parse_http_address("0.0.0.0:65535", "--http").port, 65535);
  EXPECT_EQ(parse_http_address("127.0.0.1:0", "--http").port, 0);
  EXPECT_EQ(parse_http_address("localhost:9000", "--http").host, "127.0.0.1");
}

TEST(HttpAddress, RefusesMalformedValuesWithOneLineNamingThem) {
  for (const char* bad : {"", ":80", "127.0.0.1", "127.0.0.1:", "127.0.0.1:65536", "127.0.0.1:-1",
                          "127.0.0.1:80x", "example:80", "1.2.3:80", "127.0.0.1:8080:1", "[::1]:80"}) {
    try {
      (void)parse_http_address(bad, "--http");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(std::string("--http = '") + bad + "'", 0), 0u) << message;
      EXPECT_NE(message.find("0..65535"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace retreat::bridge
