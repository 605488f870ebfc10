#include "retreat/bridge/command_line.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "retreat/core/paths.hpp"
#include "retreat/scenario/program_options.hpp"

namespace retreat::bridge {

std::variant<BridgeCommandLine, int> parse_command_line(int argc, char** argv) {
  constexpr const char* program = "retreat-bridge";
  CLI::App app{
      "retreat-bridge: live dashboard, JSON API, Prometheus metrics and reports of a "
      "voluntary-retreat swarm"};
  scenario::CommonOptions common;
  BridgeCommandLine out;
  std::string http;
  scenario::add_common_options(app, common);
  app.get_option("--scenario")->required(false);  // not with --report
  app.add_option("--http", http,
                 "HOST:PORT to serve on (overrides bridge.http; port 0 picks a free one)");
  app.add_option("--out", out.out_dir,
                 "run directory: record agent statuses, serve its files, write report.html");
  app.add_option("--report", out.report_dir,
                 "write DIR/report.html for a finished run (or seed_* runs) and exit");
  app.add_option("--replay", out.replay,
                 "serve the dashboard of a recording (retreat-record's FILE) with a time slider; no DDS");
  std::string token_file;
  bool no_token = false;
  app.add_option("--tls-cert", out.tls_cert, "serve HTTPS with this PEM certificate chain (with --tls-key)");
  app.add_option("--tls-key", out.tls_key, "the PEM private key of --tls-cert");
  app.add_option("--token-file", token_file,
                 "every request must carry the token in FILE (Authorization: Bearer, or open /?token=...); "
                 "required beyond loopback");
  app.add_flag("--no-token", no_token,
               "serve beyond loopback without a token: anyone who reaches the port sees the run and its files");
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<BridgeCommandLine, int> {
    if (!out.report_dir.empty()) return out;
    if (out.tls_cert.empty() != out.tls_key.empty()) {
      throw scenario::ConfigError(std::string(out.tls_cert.empty() ? "--tls-key" : "--tls-cert") +
                                  " without " + (out.tls_cert.empty() ? "--tls-cert" : "--tls-key") +
                                  ": HTTPS needs the certificate and its private key");
    }
    if (!token_file.empty() && no_token) throw scenario::ConfigError("--token-file and --no-token: give one");
    if (!token_file.empty()) out.token = read_token_file(token_file);
    // Beyond loopback the bridge serves the run's files to whoever reaches it: a token, or a
    // deliberate --no-token (docs/security.md).
    const auto guard = [&] {
      if (!is_loopback(out.address.host) && out.token.empty() && !no_token) {
        throw scenario::ConfigError(out.address_origin + " = '" + out.address.host + ":" +
                                    std::to_string(out.address.port) +
                                    "' is beyond loopback: give --token-file FILE (and --tls-cert/--tls-key), or "
                                    "--no-token to serve anyone who reaches it (docs/security.md)");
      }
      return out;
    };
    if (!out.replay.empty()) {
      // The recording holds the run's scenario; nothing joins DDS and nothing is recorded.
      for (const auto* option : {"--scenario", "--dds", "--domain", "--set", "--out", "--print-config"}) {
        if (app.count(option) > 0) {
          throw scenario::ConfigError(std::string(option) + " with --replay: the recording holds the run's scenario, "
                                      "and a replay joins no DDS and records nothing");
        }
      }
      out.address_origin = http.empty() ? "bridge.http" : "--http";
      out.address = parse_http_address(http.empty() ? scenario::Scenario{}.bridge.http : http, out.address_origin);
      return guard();
    }
    if (common.scenario_path.empty())
      throw scenario::ConfigError("--scenario is required (or --report DIR, or --replay FILE)");
    out.scenario = scenario::load_scenario(common);
    out.address_origin = http.empty() ? "bridge.http" : "--http";
    out.address =
        parse_http_address(http.empty() ? out.scenario.bridge.http : http, out.address_origin);
    out.print_config = common.print_config;
    return guard();
  });
}

bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  in_addr address{};
  return ::inet_pton(AF_INET, host.c_str(), &address) == 1 && (ntohl(address.s_addr) >> 24) == 127;
}

std::string read_token_file(const std::string& path) {
  const auto text = retreat::read_file(path);
  if (!text) throw std::invalid_argument("--token-file '" + path + "': cannot read it as a file");
  std::string token = *text;
  while (!token.empty() && (token.back() == '\n' || token.back() == '\r')) token.pop_back();
  const bool allowed = std::all_of(token.begin(), token.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_' || c == '~' || c == '+' ||
           c == '/';
  });
  if (token.size() < 16 || token.size() > 4096 || !allowed) {
    throw std::invalid_argument("--token-file '" + path + "': the token must be 16 to 4096 characters of A-Z a-z 0-9 "
                                "- . _ ~ + / on one line (e.g. openssl rand -hex 32 > FILE), got " +
                                std::to_string(token.size()) + (allowed ? "" : " with others"));
  }
  return token;
}

}  // namespace retreat::bridge
