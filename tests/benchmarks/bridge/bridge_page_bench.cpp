// The dashboard with N robots (issue 18), measured in headless Chromium: a scripted swarm
// (retreat_scripted_swarm: telemetry and poses 10 times a second, every robot's status once a
// second) over DDS, retreat-bridge, and the page. Run by deploy/bench/bridge_page.sh.
//
//   bridge_page_bench VENDOR DOMAIN SECONDS N...   (the programs' paths are compiled in)
//
// Per N, one line of JSON:
//   first_plot_ms   the page's time from its navigation to the first population plot
//                   (performance.now() when the first point was plotted)
//   frames_per_s    frames Chromium ran (requestAnimationFrame) per second while the states
//                   came in: the page's responsiveness (60 when nothing blocks it)
//   draws_per_s     dashboard draws per second (one per state received, at most 10)
//   draw_ms         one draw (counters, table, arena, histogram, plot): p50, p99, max
//   draw_capacity   1000 / p99 draw ms: the draws per second the page could make
//   written, received   samples per topic the swarm wrote and the bridge's readers took
// Nothing here passes or fails: the figures go to docs/benchmarks.md.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

#include "bridge_support.hpp"
#include "retreat/testing/process.hpp"

namespace {

using namespace std::chrono_literals;
using nlohmann::json;
namespace fs = std::filesystem;
namespace tb = retreat::testing::bridge;
using retreat::testing::ChildProcess;
using retreat::testing::eventually;

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(std::lround(p / 100.0 * static_cast<double>(v.size() - 1))))];
}

/// `name{topic="t"} value` lines of a Prometheus text, for one family.
json by_topic(const std::string& metrics, const std::string& name) {
  json out = json::object();
  std::size_t at = 0;
  const std::string start = name + "{topic=\"";
  while ((at = metrics.find(start, at)) != std::string::npos) {
    const auto topic_end = metrics.find('"', at + start.size());
    const auto topic = metrics.substr(at + start.size(), topic_end - at - start.size());
    const auto value_at = metrics.find(' ', topic_end);
    out[topic] = std::stod(metrics.substr(value_at + 1));
    at = value_at;
  }
  return out;
}

json measure(const std::string& vendor, int domain, int seconds, int robots, const std::string& dir) {
  fs::create_directories(dir);
  const std::string scenario = dir + "/scenario.yaml";
  const double side = std::sqrt(robots / 1.6);
  std::ofstream(scenario) << "name: bridge-page-" << robots << "\n"
                          << "arena: {encounter_model: physical, shape: rectangle, width: " << side
                          << ", height: " << side << ", robots_inside: " << robots << ", robots_waiting: 0}\n";
  auto b = tb::start_bridge({"--scenario", scenario, "--dds", vendor, "--domain", std::to_string(domain), "--http",
                             "127.0.0.1:0"},
                            dir + "/bridge.log", 60s);
  json row{{"robots", robots}};
  if (b.url.empty()) {
    row["error"] = "the bridge did not start: " + retreat::testing::read_file(b.log);
    return row;
  }
  ChildProcess swarm({RETREAT_SCRIPTED_SWARM_BIN, vendor, std::to_string(domain), std::to_string(robots), "10", std::to_string(seconds)},
                     dir + "/swarm.log");
  // The swarm's first samples reach the bridge before the page is opened: what a viewer who
  // opens the dashboard of a running swarm sees.
  eventually(
      [&] {
        const auto r = tb::get(b.port, "/api/state");
        return r && json::parse(r->body)["agents"].size() == static_cast<std::size_t>(robots);
      },
      60s);
  tb::Browser browser(dir + "/chromium-profile", 1440, 1000, dir + "/chromium.log");
  browser.navigate(b.url);
  json probe;
  eventually(
      [&] {
        probe = browser.evaluate("window.retreatDashboard && window.retreatDashboard.firstPlotMs");
        return probe.is_number() && probe.get<double>() > 0;
      },
      60s);
  row["first_plot_ms"] = probe.is_number() ? std::round(probe.get<double>()) : -1;
  browser.evaluate(
      "window.benchFrames = 0; (function frame() { window.benchFrames++; requestAnimationFrame(frame); })();"
      "window.benchDraws0 = window.retreatDashboard.arenaFrames; true");
  const auto window_s = std::min(10, seconds / 2);
  std::this_thread::sleep_for(std::chrono::seconds(window_s));
  const auto seen = browser.evaluate(
      "({frames: window.benchFrames, draws: window.retreatDashboard.arenaFrames - window.benchDraws0,"
      "  drawn: window.retreatDashboard.robotsDrawn, ms: window.retreatDashboard.drawMs})");
  row["frames_per_s"] = std::round(10.0 * seen["frames"].get<double>() / window_s) / 10.0;
  row["draws_per_s"] = std::round(10.0 * seen["draws"].get<double>() / window_s) / 10.0;
  row["robots_drawn"] = seen["drawn"];
  const auto ms = seen["ms"].get<std::vector<double>>();
  const auto p99 = percentile(ms, 99);
  row["draw_ms"] = {{"p50", std::round(10 * percentile(ms, 50)) / 10}, {"p99", std::round(10 * p99) / 10},
                    {"max", ms.empty() ? -1.0 : std::round(10 * *std::max_element(ms.begin(), ms.end())) / 10}};
  row["draw_capacity_per_s"] = p99 > 0 ? std::round(1000.0 / p99) : -1;
  row["browser_errors"] = browser.errors().size();

  swarm.wait_for(std::chrono::seconds(seconds + 120));
  const auto log = retreat::testing::read_file(dir + "/swarm.log");
  const auto brace = log.rfind('{');
  row["written"] = brace == std::string::npos ? json() : json::parse(log.substr(brace), nullptr, false);
  std::this_thread::sleep_for(500ms);  // the bridge's counters are refreshed every 200 ms
  const auto metrics = tb::get(b.port, "/metrics", 30s);
  row["received"] = metrics ? by_topic(metrics->body, "retreat_bridge_samples_total") : json();
  b.process->stop();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: bridge_page_bench VENDOR DOMAIN SECONDS N...\n");
    return 2;
  }
  const std::string vendor = argv[1];
  const int domain = std::stoi(argv[2]);
  const int seconds = std::stoi(argv[3]);
  const std::string out = fs::temp_directory_path() / ("bridge_page_bench_" + std::to_string(::getpid()));
  for (int i = 4; i < argc; ++i) {
    const int n = std::stoi(argv[i]);
    std::printf("%s\n", measure(vendor, domain, seconds, n, out + "/" + std::to_string(n)).dump().c_str());
    std::fflush(stdout);
  }
  fs::remove_all(out);
  return 0;
}
