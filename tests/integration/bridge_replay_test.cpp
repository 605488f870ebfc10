// retreat-bridge --replay FILE: the dashboard of a recording, moved by its slider.
//   - /api/replay gives the recording's span and moves: a seek, play to the end, pause; bad
//     parameters get 400 with one line;
//   - headless Chromium: the page shows the slider over the recording's ticks; moving it to the
//     end and back redraws the arena at those ticks and the population series with them; play
//     runs to the last tick; no page script error.
// The recording is the committed short run (tests/fuzz/corpus/recording: Cyclone DDS, 7 robots,
// 50 ticks, poses at ticks 0, 17, 34 and 50). No DDS.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bridge_support.hpp"

namespace retreat {
namespace {

using nlohmann::json;
using testing::eventually;
namespace fs = std::filesystem;
namespace tb = testing::bridge;

const std::string recording = RETREAT_SOURCE_DIR "/tests/fuzz/corpus/recording/cyclonedds-3-robots.mcap";

/// POST /api/replay?query on a fresh connection; the status line and body.
tb::Reply post(int port, const std::string& query) {
  const auto raw = tb::raw_exchange(
      port, "POST /api/replay?" + query + " HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
      std::chrono::seconds(5));
  tb::Reply r;
  r.status = tb::status_of(raw);
  const auto body = raw.find("\r\n\r\n");
  if (body != std::string::npos) r.body = raw.substr(body + 4);
  return r;
}

TEST(BridgeReplay, TheApiMovesThroughTheRecording) {
  const std::string dir = ::testing::TempDir() + "/bridge_replay_api";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto b = tb::start_bridge({"--replay", recording, "--http", "127.0.0.1:0"}, dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  const auto r = tb::get(b.port, "/api/replay");
  ASSERT_TRUE(r && r->status == 200);
  const auto p = json::parse(r->body);
  EXPECT_EQ(p["first_tick"], 0);
  EXPECT_EQ(p["last_tick"], 50);
  EXPECT_EQ(p["tick"], 0);
  EXPECT_FALSE(p["playing"].get<bool>());
  EXPECT_TRUE(p["replaying"].get<bool>());

  auto seek = post(b.port, "tick=34");
  ASSERT_EQ(seek.status, 200) << seek.body;
  EXPECT_EQ(json::parse(seek.body)["tick"], 34);
  auto state = json::parse(tb::get(b.port, "/api/state")->body);
  EXPECT_EQ(state["telemetry"]["tick"], 34);
  EXPECT_EQ(state["poses"]["tick"], 34);
  const auto points_at_34 = state["history"]["points"].get<int>();
  // Back to the start: the state is the one at tick 0 again, its series one point long.
  ASSERT_EQ(post(b.port, "tick=0").status, 200);
  state = json::parse(tb::get(b.port, "/api/state")->body);
  EXPECT_EQ(state["telemetry"]["tick"], 0);
  EXPECT_EQ(state["history"]["points"], 1);
  EXPECT_GT(points_at_34, 1);
  // Play to the end (50 ticks of 0.03 s at 10 simulated s per wall s: 0.15 s), then it stops.
  ASSERT_EQ(post(b.port, "play=1&speed=10").status, 200);
  const bool ended = eventually(
      [&] {
        const auto now = json::parse(tb::get(b.port, "/api/replay")->body);
        return now["tick"] == 50 && !now["playing"].get<bool>();
      },
      testing::hang_ceiling);
  EXPECT_TRUE(ended);
  EXPECT_EQ(json::parse(tb::get(b.port, "/api/state")->body)["telemetry"]["tick"], 50);

  for (const auto& [query, text] : std::vector<std::pair<std::string, std::string>>{
           {"tick=x", "400 tick 'x': a whole number"},
           {"tick=1.5", "400 tick '1.5': a whole number"},
           {"play=1&speed=0", "400 speed '0'"},
           {"play=yes", "400 play 'yes': 1 or 0"},
           {"speed=3", "400 speed without play=1"},
           {"rewind=1", "400 unknown parameter 'rewind'"}}) {
    const auto bad = post(b.port, query);
    EXPECT_EQ(bad.status, 400) << query;
    EXPECT_EQ(bad.body.rfind(text, 0), 0u) << query << ": " << bad.body;
    EXPECT_EQ(bad.body.find('\n'), bad.body.size() - 1) << "one line: " << bad.body;
  }
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

TEST(BridgeReplay, LiveBridgesHaveNoReplay) {
  // A live bridge says it is not replaying (the page then shows no slider) and refuses moves.
  const std::string dir = ::testing::TempDir() + "/bridge_replay_live";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir + "/s.yaml") << "name: live\n";
  auto b = tb::start_bridge({"--scenario", dir + "/s.yaml", "--dds", "inmemory", "--http", "127.0.0.1:0"},
                            dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  const auto r = tb::get(b.port, "/api/replay");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(json::parse(r->body), json({{"replaying", false}}));
  const auto refused = post(b.port, "tick=3");
  EXPECT_EQ(refused.status, 409);
  EXPECT_EQ(refused.body.rfind("409 not replaying a recording", 0), 0u) << refused.body;
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

TEST(BridgeBrowser, AReplayMovesWithItsSlider) {
  if (!tb::Browser::available()) GTEST_SKIP() << "no chromium (deploy/install-deps.sh installs it)";
  const std::string dir = ::testing::TempDir() + "/bridge_replay_browser";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto b = tb::start_bridge({"--replay", recording, "--http", "127.0.0.1:0"}, dir + "/bridge.log");
  ASSERT_FALSE(b.url.empty()) << testing::read_file(b.log);
  tb::Browser browser(dir + "/chromium-profile", 1440, 1000, dir + "/chromium.log");
  browser.navigate(b.url);
  const auto page = [&] {
    return browser.evaluate(
        "({replay: window.retreatDashboard.replay, hidden: document.getElementById('replay').hidden,"
        "  min: document.getElementById('replay-slider').min, max: document.getElementById('replay-slider').max,"
        "  arena: Number(document.getElementById('arena').dataset.tick),"
        "  points: window.retreatDashboard.points, link: document.getElementById('link').dataset.state})");
  };
  json p;
  ASSERT_TRUE(eventually(
      [&] {
        p = page();
        return p.is_object() && p["replay"].is_object() && p["arena"] == 0;
      },
      testing::hang_ceiling))
      << p.dump();
  EXPECT_FALSE(p["hidden"].get<bool>());
  EXPECT_EQ(p["min"], "0");
  EXPECT_EQ(p["max"], "50");
  EXPECT_EQ(p["link"], "replay");
  // The slider to the end, as a person drags it: the arena is drawn at the last poses' tick and
  // the series has the run's points.
  const std::string move = "(() => { const s = document.getElementById('replay-slider'); s.value = '%'; "
                           "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change')); return true; })()";
  const auto slide_to = [&](const std::string& tick) {
    auto js = move;
    js.replace(js.find('%'), 1, tick);
    browser.evaluate(js);
  };
  slide_to("50");
  ASSERT_TRUE(eventually(
      [&] {
        p = page();
        return p["arena"] == 50 && p["replay"]["tick"] == 50 && p["points"].get<int>() > 1;
      },
      testing::hang_ceiling))
      << p.dump();
  const auto points_at_end = p["points"].get<int>();
  slide_to("17");
  ASSERT_TRUE(eventually(
      [&] {
        p = page();
        return p["arena"] == 17 && p["points"].get<int>() < points_at_end;
      },
      testing::hang_ceiling))
      << p.dump();
  // Play: it runs to the end and stops there.
  browser.evaluate("document.getElementById('replay-play').click(), true");
  ASSERT_TRUE(eventually(
      [&] {
        p = page();
        return p["arena"] == 50 && p["replay"]["tick"] == 50 && !p["replay"]["playing"].get<bool>();
      },
      testing::hang_ceiling))
      << p.dump();
  browser.screenshot(tb::output_dir() + "/bridge_replay.png");
  EXPECT_TRUE(browser.errors().empty()) << browser.errors().front();
  EXPECT_EQ(b.process->stop(), 0) << testing::read_file(b.log);
}

}  // namespace
}  // namespace retreat
