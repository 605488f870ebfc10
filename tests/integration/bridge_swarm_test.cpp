// retreat-bridge with a real swarm (retreat-arena and four retreat-agent processes):
//   - a bridge started after the arena shows the current population within one second;
//   - headless Chromium shows the dashboard live: the population figure and the arena drawing
//     update, a screenshot is saved, no page script error; at the end of the run the bridge
//     writes report.html, which loads without a script error too.
// DDS domains 99 and 100. Every process is stopped by PID.

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "bridge_support.hpp"
#include "prometheus_check.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/testing/domains.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;
using testing::ChildProcess;
using testing::eventually;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;
namespace tb = testing::bridge;

bool built(const std::string& vendor) {
  const auto v = transport::dds_vendors();
  return std::find(v.begin(), v.end(), vendor) != v.end();
}

struct Swarm {
  std::vector<ChildProcess> agents;
  std::optional<ChildProcess> arena;
  ~Swarm() {
    if (arena) arena->stop();
    for (auto& a : agents) a.stop();
  }
};

void start_swarm(Swarm& s, const std::string& scenario, const std::string& vendor, int domain, const std::string& out) {
  for (int i = 0; i < 4; ++i) {
    s.agents.emplace_back(std::vector<std::string>{RETREAT_AGENT_BIN, "--robot-id", std::to_string(i), "--scenario",
                                                   scenario, "--dds", vendor, "--domain", std::to_string(domain)},
                          out + "_agent" + std::to_string(i) + ".log");
  }
  s.arena.emplace(std::vector<std::string>{RETREAT_ARENA_BIN, "--scenario", scenario, "--dds", vendor, "--domain",
                                           std::to_string(domain), "--out", out},
                  out + "_arena.log");
}

/// The newest arena telemetry on `domain`, read by a participant of the test's own.
class Watch {
 public:
  Watch(const std::string& vendor, int domain)
      : transport_(transport::make_transport(vendor, {domain, "bridge-test-watch", "", ""})),
        reader_(transport_->create_reader<wire::ArenaTelemetry>(
            {wire::arena_telemetry_topic("retreat"), transport::QosIntent::state()})) {}
  std::optional<wire::ArenaTelemetry> latest(std::chrono::milliseconds wait) {
    transport_->wait(wait);
    for (auto& t : reader_.take()) last_ = t;
    return last_;
  }

 private:
  std::unique_ptr<transport::Transport> transport_;
  transport::Reader<wire::ArenaTelemetry> reader_;
  std::optional<wire::ArenaTelemetry> last_;
};

TEST(BridgeSwarm, ABridgeStartedAfterTheArenaShowsTheCurrentPopulation) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const int domain = testing::domains::bridge.at(1);
  const std::string dir = ::testing::TempDir() + "/bridge_late";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scenario = dir + "/scenario.yaml";
  // Kinetic world in real time at 5x: 60 simulated seconds last 12 wall seconds, robots leave
  // now and then (K_p = 0.1), so the population is a moving target.
  std::ofstream(scenario) << "name: bridge-late\nseed: 5\n"
                          << "agent: {L: 5, dt: 0.03, K_p: 0.1, lambda_in: 0.02}\n"
                          << "arena: {encounter_model: kinetic, robots_inside: 3, robots_waiting: 1}\n"
                          << "run: {mode: realtime, speed: 5, duration: 60, agent_timeout: 3, startup_timeout: 20}\n";
  Swarm swarm;
  start_swarm(swarm, scenario, vendor, domain, dir + "/run");
  Watch watch(vendor, domain);
  std::optional<wire::ArenaTelemetry> seen;
  ASSERT_TRUE(eventually([&] { return (seen = watch.latest(50ms)) && seen->tick > 30; }, retreat::testing::hang_ceiling))
      << testing::read_file(dir + "/run_arena.log");

  const auto started = Clock::now();
  auto b = tb::start_bridge({"--scenario", scenario, "--dds", vendor, "--domain", std::to_string(domain), "--http",
                             "127.0.0.1:0"},
                            dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  const auto serving = Clock::now();
  json state;
  const bool shown = eventually(
      [&] {
        const auto r = tb::get(b.port, "/api/state", 2s);
        if (!r || r->status != 200) return false;
        state = json::parse(r->body);
        return !state["telemetry"].is_null();
      },
      retreat::testing::hang_ceiling);
  const auto shown_at = Clock::now();
  ASSERT_TRUE(shown) << testing::read_file(b.log);
  const double since_serving = std::chrono::duration<double>(shown_at - serving).count();
  const double since_start = std::chrono::duration<double>(shown_at - started).count();
  std::fprintf(stderr, "late bridge (%s): population shown %.3f s after it served, %.3f s after it started\n",
               vendor.c_str(), since_serving, since_start);
  // How soon is printed, not asserted (a loaded machine is slow, not wrong); what is asserted is
  // that the state shown is the arena's current one, which the bridge can only have from the
  // durable (transient-local) telemetry it joined late.
  // The population shown is the arena's current one: the newest our own reader has seen (the
  // arena publishes 10 times per simulated second; allow the one sample in flight).
  const auto now = watch.latest(0ms);
  ASSERT_TRUE(now);
  EXPECT_GE(state["telemetry"]["tick"].get<std::int64_t>(), seen->tick);
  const auto inside = state["telemetry"]["inside"].get<std::uint32_t>();
  EXPECT_LE(inside, 4u);
  if (state["telemetry"]["tick"].get<std::int64_t>() == now->tick) {
    EXPECT_EQ(inside, now->inside);
  }
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

// The figures page's heat map (retreat-experiment sweep draws its results with it), in Chromium:
// one coloured cell per value, green at `low`, red at `high`, grey for a missing value.
TEST(BridgeBrowser, TheFiguresPageDrawsAHeatMapAsColouredCells) {
  if (!tb::Browser::available()) GTEST_SKIP() << "no chromium (deploy/install-deps.sh installs it)";
  const std::string dir = ::testing::TempDir() + "/figures_heatmap";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const json page = {
      {"title", "heat"},
      {"sections",
       {{{"heading", "h"},
         {"figures",
          {{{"id", "map"}, {"title", "Map"}, {"x_label", "rule"}, {"y_label", "cell"},
            {"heatmap", {{"rows", {"a", "b"}}, {"columns", {"x", "y", "z"}},
                         {"values", {{0.0, 0.25, 0.5}, {1.0, nullptr, -3.0}}},
                         {"text", {{"zero", "quarter", "half"}, {"beyond", "none", "below"}}},
                         {"low", 0.0}, {"high", 0.5}}}}}}}}}};
  retreat::report::write_figures_page(page, dir + "/report.html");
  tb::Browser browser(dir + "/chromium-profile", 1000, 800, dir + "/chromium.log");
  browser.navigate("file://" + dir + "/report.html");
  const auto cells = browser.evaluate(
      "Array.from(document.querySelectorAll('#figure-map td.heat')).map((c) => "
      "[c.textContent, getComputedStyle(c).backgroundColor])");
  ASSERT_TRUE(cells.is_array()) << cells.dump();
  ASSERT_EQ(cells.size(), 6u) << cells.dump();
  const auto colour = [&](std::size_t i) { return cells[i][1].get<std::string>(); };
  EXPECT_EQ(cells[0][0], "zero");
  EXPECT_EQ(cells[4][0], "none");
  // hsl(120, 70%, 78%) is rgb(160, 238, 160); hsl(0, 70%, 78%) is rgb(238, 160, 160).
  EXPECT_EQ(colour(0), "rgb(160, 238, 160)");
  EXPECT_EQ(colour(2), "rgb(238, 160, 160)");
  EXPECT_EQ(colour(3), colour(2)) << "beyond high: the end colour";
  EXPECT_EQ(colour(5), colour(0)) << "below low: the end colour";
  EXPECT_EQ(colour(4), "rgb(226, 232, 240)") << "a missing value is grey";
  EXPECT_NE(colour(1), colour(0));
  EXPECT_NE(colour(1), colour(2));
  EXPECT_TRUE(browser.errors().empty()) << browser.errors().front();
  fs::remove_all(dir);
}

TEST(BridgeBrowser, ChromiumShowsTheLiveSwarmAndTheReport) {
  if (!tb::Browser::available()) GTEST_SKIP() << "no chromium (deploy/install-deps.sh installs it)";
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  const int domain = testing::domains::bridge.at(2);
  const std::string dir = ::testing::TempDir() + "/bridge_browser";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scenario = dir + "/scenario.yaml";
  const std::string run = dir + "/run";
  // The physical world (positions to draw), 3 robots inside and 1 waiting, in real time at 4x:
  // 48 simulated seconds take 12 wall seconds. Encounters recorded for the report.
  std::ofstream(scenario) << "name: bridge-browser\nseed: 7\n"
                          << "agent: {L: 6, dt: 0.03, K_p: 0.1, lambda_in: 0.02}\n"
                          << "arena: {encounter_model: physical, robots_inside: 3, robots_waiting: 1, "
                             "record_encounters: true}\n"
                          << "run: {mode: realtime, speed: 4, duration: 48, agent_timeout: 3, startup_timeout: 20}\n";
  // The bridge first, so that it records every agent status from the start.
  auto b = tb::start_bridge({"--scenario", scenario, "--dds", vendor, "--domain", std::to_string(domain), "--http",
                             "127.0.0.1:0", "--out", run},
                            dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  // The page next, with its event stream open, and only then the swarm: a real-time run lasts
  // 12 s, and Chromium on a loaded machine can take longer than that to start and load a page
  // (seen: the page came after the run had ended, and drew its last state only).
  tb::Browser browser(dir + "/chromium-profile", 1440, 1000, dir + "/chromium.log");
  browser.navigate(b.url);
  // Open: "live" on the stream's open event, "idle" once no state has come for 3 s.
  ASSERT_TRUE(eventually(
      [&] {
        const auto link = browser.evaluate("document.getElementById('link').dataset.state");
        return link == "live" || link == "idle";
      },
      retreat::testing::hang_ceiling));
  Swarm swarm;
  start_swarm(swarm, scenario, vendor, domain, run);
  // Wait until the page shows a population from the swarm, has drawn the arena with several
  // different poses, and plotted a few points.
  json probe;
  std::set<std::int64_t> ticks;
  const bool live = eventually(
      [&] {
        probe = browser.evaluate(
            "({inside: document.getElementById('inside').textContent,"
            "  tick: Number(document.getElementById('arena').dataset.tick),"
            "  frames: window.retreatDashboard ? window.retreatDashboard.arenaFrames : 0,"
            "  robots: window.retreatDashboard ? window.retreatDashboard.robotsDrawn : 0,"
            "  points: window.retreatDashboard ? window.retreatDashboard.points : 0,"
            "  link: document.getElementById('link').dataset.state})");
        if (!probe.is_object()) return false;
        if (probe["tick"].is_number() && probe["tick"].get<double>() >= 0) ticks.insert(probe["tick"].get<std::int64_t>());
        const auto inside = probe["inside"].get<std::string>();
        return !inside.empty() && std::isdigit(static_cast<unsigned char>(inside[0])) && ticks.size() >= 3 &&
               probe["robots"].get<int>() > 0 && probe["points"].get<int>() >= 5;
      },
      retreat::testing::hang_ceiling);
  // The picture: later in the run (36 of 48 simulated seconds) there is more to see; the run
  // goes on until then anyway.
  eventually(
      [&] {
        const auto t = browser.evaluate("window.retreatDashboard.time");
        return t.is_number() && t.get<double>() >= 36.0;
      },
      retreat::testing::hang_ceiling);
  std::this_thread::sleep_for(300ms);
  const std::string shot = tb::output_dir() + "/bridge_dashboard.png";
  browser.screenshot(shot);
  ASSERT_TRUE(live) << probe.dump() << "\n" << testing::read_file(b.log);
  EXPECT_EQ(probe["link"], "live");
  EXPECT_TRUE(fs::file_size(shot) > 10000) << shot;
  EXPECT_TRUE(browser.errors().empty()) << [&] {
    std::string all;
    for (const auto& e : browser.errors()) all += e + "\n";
    return all;
  }();

  // The run ends; the bridge sees summary.json and writes report.html.
  ASSERT_TRUE(swarm.arena->wait_for(retreat::testing::hang_ceiling).has_value()) << testing::read_file(run + "_arena.log");
  ASSERT_TRUE(eventually([&] { return fs::exists(run + "/report.html"); }, retreat::testing::hang_ceiling)) << testing::read_file(b.log);
  browser.navigate("file://" + run + "/report.html");
  ASSERT_TRUE(eventually([&] { return browser.evaluate("document.body.dataset.ready") == "1"; }, retreat::testing::hang_ceiling));
  // Population, throughput, estimates; inter-encounter times too when the run had two gaps.
  EXPECT_GE(browser.evaluate("document.querySelectorAll('.uplot').length").get<int>(), 3);
  browser.screenshot(tb::output_dir() + "/bridge_report.png");
  EXPECT_TRUE(browser.errors().empty()) << browser.errors().front();
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
  std::fprintf(stderr, "screenshots: %s, %s/bridge_report.png\n", shot.c_str(), tb::output_dir().c_str());
}

TEST(BridgeBrowser, TheDashboardOfAThousandRobotsDrawsThemAllWithAVirtualTable) {
  if (!tb::Browser::available()) GTEST_SKIP() << "no chromium (deploy/install-deps.sh installs it)";
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  // BridgeApi's domain, with topics of another prefix: neither test hears the other's.
  const int domain = testing::domains::bridge.at(0);
  const std::string prefix = "thousand";
  const std::string dir = ::testing::TempDir() + "/bridge_thousand";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scenario = dir + "/scenario.yaml";
  // The scripted swarm's square: 1,000 robots at 1.6 robots/m² (25 m × 25 m).
  std::ofstream(scenario) << "name: bridge-thousand\n"
                          << "arena: {encounter_model: physical, shape: rectangle, width: 25, height: 25, "
                             "robots_inside: 1000, robots_waiting: 0}\n"
                          << "dds: {prefix: " << prefix << "}\n";
  auto b = tb::start_bridge({"--scenario", scenario, "--dds", vendor, "--domain", std::to_string(domain), "--http",
                             "127.0.0.1:0"},
                            dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  // Poses and telemetry 10 times a second, every robot's status once a second, for 30 s.
  ChildProcess swarm({RETREAT_SCRIPTED_SWARM_BIN, vendor, std::to_string(domain), "1000", "10", "30", prefix},
                     dir + "/swarm.log");

  tb::Browser browser(dir + "/chromium-profile", 1440, 1000, dir + "/chromium.log");
  browser.navigate(b.url);
  json probe;
  const auto look = [&] {
    probe = browser.evaluate(
        "(() => { const p = window.retreatDashboard || {};"
        "  return {robots: p.robotsDrawn, agents: p.agents, shown: p.agentRowsShown, points: p.points,"
        "          plotted: p.firstPlotMs,"
        "          rows: document.querySelectorAll('#agents tbody tr:not(.spacer)').length,"
        "          last: (document.querySelector('#agents tbody tr:not(.spacer):last-of-type td') || {}).textContent}; })()");
    return probe.is_object();
  };
  // Every robot drawn, every agent in the table's data, the population plotted.
  ASSERT_TRUE(eventually(
      [&] {
        return look() && probe["robots"] == 1000 && probe["agents"] == 1000 && probe["points"].get<int>() >= 3 &&
               probe["plotted"].get<double>() > 0;
      },
      retreat::testing::hang_ceiling))
      << probe.dump() << "\n" << testing::read_file(b.log) << testing::read_file(dir + "/swarm.log");
  // The table holds a view's worth of rows, not a thousand: those at the top first.
  EXPECT_EQ(probe["rows"], probe["shown"]);
  EXPECT_LE(probe["shown"].get<int>(), 40);
  EXPECT_GE(probe["shown"].get<int>(), 5);
  // Scrolled to the end, the last robots' rows are the ones in the table.
  browser.evaluate("(() => { const box = document.getElementById('agents').parentElement;"
                   " box.scrollTop = box.scrollHeight; return true; })()");
  EXPECT_TRUE(eventually([&] { return look() && probe["last"] == "999"; }, retreat::testing::hang_ceiling))
      << probe.dump();
  EXPECT_LE(probe["rows"].get<int>(), 40);
  browser.screenshot(tb::output_dir() + "/bridge_thousand.png");
  EXPECT_TRUE(browser.errors().empty()) << [&] {
    std::string all;
    for (const auto& e : browser.errors()) all += e + "\n";
    return all;
  }();

  // The swarm ends; the bridge heard every robot and no sample it took was invalid.
  const auto code = swarm.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0) << testing::read_file(dir + "/swarm.log");
  const auto r = tb::get(b.port, "/api/state", 60s);
  ASSERT_TRUE(r);
  EXPECT_EQ(json::parse(r->body)["agents"].size(), 1000u);
  const auto metrics = tb::get(b.port, "/metrics", 60s);
  ASSERT_TRUE(metrics);
  EXPECT_EQ(metrics->status, 200) << metrics->body;
  const auto m = testing::prometheus::parse(metrics->body);
  EXPECT_TRUE(m.errors.empty()) << testing::prometheus::describe(m);
  EXPECT_EQ(m.value("retreat_bridge_samples_invalid_total"), 0);
  // Each robot's status once a second for 30 s: every robot's at least once. (How many of the
  // written samples arrive is the benchmark's figure: a keep-last-1 reader keeps the newest of
  // each robot, so a bridge delayed on a loaded machine may skip one, by design.)
  EXPECT_GE(m.value("retreat_bridge_samples_total", {{"topic", "agent_status"}}), 1000);
  EXPECT_EQ(m.value("retreat_lambda_hat_count"), 1000);
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

}  // namespace
}  // namespace retreat
