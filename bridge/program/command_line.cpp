#include "retreat/bridge/command_line.hpp"

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
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<BridgeCommandLine, int> {
    if (!out.report_dir.empty()) return out;
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
      return out;
    }
    if (common.scenario_path.empty())
      throw scenario::ConfigError("--scenario is required (or --report DIR, or --replay FILE)");
    out.scenario = scenario::load_scenario(common);
    out.address_origin = http.empty() ? "bridge.http" : "--http";
    out.address =
        parse_http_address(http.empty() ? out.scenario.bridge.http : http, out.address_origin);
    out.print_config = common.print_config;
    return out;
  });
}

}  // namespace retreat::bridge
