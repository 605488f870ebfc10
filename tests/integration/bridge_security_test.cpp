// retreat-bridge beyond loopback (docs/security.md): HTTPS and a bearer token, over real sockets.
//   - over HTTPS (a certificate made here with openssl, the client verifying it), a request
//     without the token, or with a wrong one, gets 401 with WWW-Authenticate; the token as a
//     bearer header or as the cookie that /?token= sets is let through; plain HTTP to the port
//     gets no answer;
//   - headless Chromium, trusting that certificate only, opens /?token=...: the page loads its
//     state with the cookie and its address keeps no token;
//   - bad TLS or token input: one line, exit code 2 (with the other refusals in bridge_input_test).
// No DDS: the bridge replays the committed recording (tests/fuzz/corpus/recording).

#include <gtest/gtest.h>
#include <httplib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bridge_support.hpp"

namespace retreat {
namespace {

namespace fs = std::filesystem;
namespace tb = testing::bridge;
using nlohmann::json;

const std::string recording = RETREAT_SOURCE_DIR "/tests/fuzz/corpus/recording/cyclonedds-3-robots.mcap";
const std::string token = "0123456789abcdef0123456789abcdef";

/// A self-signed certificate for 127.0.0.1 and its key, the token file, and the base64 SHA-256
/// of the certificate's public key (what Chromium is told to trust), in @p dir.
struct Credentials {
  std::string cert, key, token_file, spki;
};
Credentials make_credentials(const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  Credentials c{dir + "/cert.pem", dir + "/key.pem", dir + "/token", ""};
  const std::string make = "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 2 -subj /CN=127.0.0.1"
                           " -addext subjectAltName=IP:127.0.0.1 -keyout " + c.key + " -out " + c.cert + " 2>" + dir + "/openssl.log";
  EXPECT_EQ(std::system(make.c_str()), 0) << testing::read_file(dir + "/openssl.log");
  const std::string spki = "openssl x509 -in " + c.cert + " -pubkey -noout | openssl pkey -pubin -outform der | "
                           "openssl dgst -sha256 -binary | base64 > " + dir + "/spki";
  EXPECT_EQ(std::system(spki.c_str()), 0);
  c.spki = testing::read_file(dir + "/spki");
  while (!c.spki.empty() && c.spki.back() == '\n') c.spki.pop_back();
  std::ofstream(c.token_file) << token << "\n";
  return c;
}

tb::Bridge start_secure_bridge(const Credentials& c, const std::string& log) {
  return tb::start_bridge({"--replay", recording, "--http", "127.0.0.1:0", "--tls-cert", c.cert, "--tls-key", c.key,
                           "--token-file", c.token_file},
                          log);
}

TEST(BridgeSecurity, OverHttpsEveryRequestNeedsTheTokenAsABearerHeaderOrItsCookie) {
  const std::string dir = ::testing::TempDir() + "/bridge_security_api";
  const auto c = make_credentials(dir);
  auto b = start_secure_bridge(c, dir + "/bridge.log");
  ASSERT_EQ(b.url.rfind("https://127.0.0.1:", 0), 0u) << testing::read_file(b.log);

  httplib::SSLClient client("127.0.0.1", b.port);
  client.set_ca_cert_path(c.cert.c_str());
  client.enable_server_certificate_verification(true);
  client.set_connection_timeout(std::chrono::seconds(10));
  client.set_read_timeout(std::chrono::seconds(10));

  for (const std::string path : {"/api/state", "/metrics", "/api/replay", "/", "/app.js"}) {
    const auto none = client.Get(path);
    ASSERT_TRUE(none) << path << ": " << httplib::to_string(none.error());
    EXPECT_EQ(none->status, 401) << path;
    EXPECT_EQ(none->get_header_value("WWW-Authenticate"), "Bearer realm=\"retreat-bridge\"") << path;
    EXPECT_EQ(std::count(none->body.begin(), none->body.end(), '\n'), 1) << none->body;
    const auto wrong = client.Get(path, {{"Authorization", "Bearer " + token.substr(1) + "x"}});
    ASSERT_TRUE(wrong);
    EXPECT_EQ(wrong->status, 401) << path;
  }
  const auto by_header = client.Get("/api/replay", {{"Authorization", "Bearer " + token}});
  ASSERT_TRUE(by_header);
  EXPECT_EQ(by_header->status, 200);
  EXPECT_EQ(json::parse(by_header->body)["last_tick"], 50);
  const auto metrics = client.Get("/metrics", {{"Authorization", "Bearer " + token}});
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200);

  // The page opened with its token: the cookie, and back to / without it.
  EXPECT_EQ(client.Get("/?token=" + token.substr(0, 16))->status, 401);
  const auto opened = client.Get("/?token=" + token);
  ASSERT_TRUE(opened);
  EXPECT_EQ(opened->status, 303);
  EXPECT_EQ(opened->get_header_value("Location"), "/");
  EXPECT_EQ(opened->get_header_value("Set-Cookie"),
            "retreat_token=" + token + "; Path=/; HttpOnly; SameSite=Strict; Secure");
  const auto by_cookie = client.Get("/api/state", {{"Cookie", "other=1; retreat_token=" + token}});
  ASSERT_TRUE(by_cookie);
  EXPECT_EQ(by_cookie->status, 200);
  EXPECT_EQ(client.Get("/api/state", {{"Cookie", "retreat_token=" + token + "0"}})->status, 401);

  // Plain HTTP on the HTTPS port: no HTTP answer.
  EXPECT_FALSE(tb::get(b.port, "/api/state", std::chrono::seconds(5)).has_value());
}

TEST(BridgeBrowser, TheDashboardOpenedWithItsTokenOverHttpsLoadsWithTheCookie) {
  if (!tb::Browser::available()) GTEST_SKIP() << "no chromium (deploy/install-deps.sh installs it)";
  const std::string dir = ::testing::TempDir() + "/bridge_security_browser";
  const auto c = make_credentials(dir);
  auto b = start_secure_bridge(c, dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  // Chromium trusts this one key, not every certificate.
  tb::Browser browser(dir + "/chromium-profile", 1280, 900, dir + "/chromium.log",
                      {"--ignore-certificate-errors-spki-list=" + c.spki});
  browser.navigate(b.url + "?token=" + token);
  json p;
  ASSERT_TRUE(testing::eventually(
      [&] {
        p = browser.evaluate(
            "({replay: window.retreatDashboard && window.retreatDashboard.replay, address: location.href,"
            "  arena: Number(document.getElementById('arena').dataset.tick),"
            "  link: document.getElementById('link').dataset.state})");
        return p.is_object() && p["replay"].is_object() && p["arena"] == 0;
      },
      testing::hang_ceiling))
      << p.dump() << "\n" << testing::read_file(b.log);
  EXPECT_EQ(p["address"], b.url);  // the token is not left in the address bar or the history
  EXPECT_EQ(p["link"], "replay");
  EXPECT_TRUE(browser.errors().empty()) << browser.errors().front();
}

}  // namespace
}  // namespace retreat
