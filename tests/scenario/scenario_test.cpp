// The scenario file: shipped scenarios load, dump and reload to the same values (in YAML and in
// JSON); the loaders refuse bad input with one line naming the key, the value and what is allowed.

#include <gtest/gtest.h>

#include <filesystem>

#include "retreat/model/optimum.hpp"
#include "retreat/scenario/json.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::scenario {
namespace {

std::vector<std::string> shipped() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(RETREAT_SCENARIOS)) {
    if (e.path().extension() == ".yaml") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ShippedScenarios, EveryShippedScenarioLoadsAndSurvivesADumpAndReload) {
  const auto files = shipped();
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const auto s = load(f);
    const auto again = parse(dump(s));
    EXPECT_EQ(dump(again), dump(s));
  }
}

TEST(ShippedScenarios, TheRobotariumScenarioHasTheExperimentsParameters) {
  const auto s = load(std::string(RETREAT_SCENARIOS) + "/robotarium-2019.yaml");
  EXPECT_EQ(s.arena.shape, physics::DomainShape::ellipse);
  EXPECT_DOUBLE_EQ(s.arena.semi_axis_x, 1.2);
  EXPECT_DOUBLE_EQ(s.arena.semi_axis_y, 0.8);
  EXPECT_EQ(s.arena.robots_inside, 8u);
  EXPECT_EQ(s.arena.robots_waiting, 4u);
  EXPECT_EQ(s.arena.queue, physics::QueueKind::finite);
  EXPECT_DOUBLE_EQ(s.model.lambda_p, 1.32);
  EXPECT_DOUBLE_EQ(s.model.lambda_d, 1.32);
  EXPECT_DOUBLE_EQ(s.model.C, 0.03);
  EXPECT_DOUBLE_EQ(s.model.delta, 0.1);
  EXPECT_DOUBLE_EQ(s.model.v, 0.1);
  EXPECT_DOUBLE_EQ(s.agent.L, 90);
  EXPECT_DOUBLE_EQ(s.agent.dt, 0.03);
  EXPECT_DOUBLE_EQ(s.agent.K_p, 0.03);
  EXPECT_DOUBLE_EQ(s.agent.lambda_in, 0.02);
  EXPECT_EQ(s.agent.controller, "paper");
  EXPECT_NEAR(model::lambda_star(s.model), 1.5076, 1e-4);
}

TEST(ShippedScenarios, LockstepScenariosRunPlansWhichRealTimeTurnsOff) {
  // Event-driven lockstep is what the shipped scenarios run (proven equal to per-tick lockstep);
  // plans are lockstep's, so switching a shipped scenario to real time needs no second override.
  for (const auto& f : shipped()) {
    SCOPED_TRACE(f);
    const auto s = load(f);
    EXPECT_EQ(s.run.mode, RunMode::lockstep);
    EXPECT_TRUE(s.run.plans);
    const auto realtime = load(f, {"run.mode=realtime"});
    EXPECT_FALSE(realtime.run.plans);
    EXPECT_FALSE(load(f, {"run.plans=false"}).run.plans);
  }
  // A scenario that does not say gets per-tick lockstep, what a per-tick robot driver speaks.
  EXPECT_FALSE(parse("run:\n  mode: lockstep\n").run.plans);
}

TEST(ScenarioLoader, OverridesApplyInOrderAndReachTheArenasCopies) {
  const auto s = parse("agent: {dt: 0.03}\n", {"agent.dt=0.05", "seed=42", "model.delta=0.12"});
  EXPECT_DOUBLE_EQ(s.agent.dt, 0.05);
  EXPECT_DOUBLE_EQ(s.arena.tick_dt, 0.05);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.arena.seed, 42u);
  EXPECT_DOUBLE_EQ(s.arena.delta, 0.12);
}

void expect_error(const std::string& yaml, const std::vector<std::string>& overrides,
                  const std::string& expected) {
  try {
    parse(yaml, overrides);
    ADD_FAILURE() << "accepted: " << yaml;
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(expected), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
  }
}

TEST(ScenarioLoader, AnUnknownKeyIsNamedWithTheKeysAllowedInItsSection) {
  expect_error("agent: {window: 90}\n", {}, "unknown key 'agent.window' in <text> (allowed in agent: L, dt, K_p, lambda_in, controller, missed_onsets, false_onsets)");
  expect_error("agnet: {L: 90}\n", {}, "unknown key 'agnet'");
  expect_error("", {"model.gamma=3"}, "unknown key 'model.gamma' in --set");
}

TEST(ScenarioLoader, AKeyGivenTwiceIsRefusedNamingIt) {
  // yaml-cpp keeps both entries of a repeated key, and the later value silently won.
  expect_error("model:\n  delta: 0.1\n  delta: 0.2\n", {}, "model.delta in <text>: given twice (again at line 3)");
  expect_error("model: {delta: 0.1}\nmodel: {v: 0.2}\n", {}, "model in <text>: given twice (again at line 2)");
  expect_error("name: a\nname: b\n", {}, "name in <text>: given twice (again at line 2)");
  // A key in two sections is two keys; --set still overrides a key the file gives.
  EXPECT_NO_THROW(parse("model: {delta: 0.1}\narena: {max_speed: 0.2}\n", {"model.delta=0.12"}));
}

TEST(ScenarioLoader, AWrongTypeNamesTheKeyAndTheValue) {
  expect_error("model: {delta: abc}\n", {}, "model.delta = 'abc': must be a number");
  expect_error("arena: {robots_inside: 2.5}\n", {}, "arena.robots_inside = '2.5': must be a whole number in 0..4294967295");
  // Past the type's range: the range, not only ">= 0" (which 4294967296 is).
  expect_error("", {"arena.robots_inside=4294967296"},
               "arena.robots_inside = '4294967296': must be a whole number in 0..4294967295");
  expect_error("", {"seed=18446744073709551616"}, "seed = '18446744073709551616': must be a whole number in 0..18446744073709551615");
  expect_error("arena: {record_encounters: maybe}\n", {}, "arena.record_encounters = 'maybe': must be true or false");
  expect_error("model: [1, 2]\n", {}, "model in <text>: must be a mapping");
}

TEST(ScenarioLoader, OutOfRangeValuesNameTheKeyTheValueAndTheRange) {
  expect_error("", {"model.delta=-0.1"}, "model.delta = -0.1: must be > 0");
  expect_error("", {"agent.dt=100"}, "agent.dt = 100: must be > 0 and <= agent.L");
  expect_error("", {"run.mode=fast"}, "run.mode = 'fast': must be one of lockstep, realtime");
  expect_error("", {"dds.domain=233"}, "dds.domain = 233: must be an integer in 0..232");
  expect_error("", {"dds.domains=0"}, "dds.domains = 0: must be an integer in 1..64");
  expect_error("", {"dds.domains=65"}, "dds.domains = 65: must be an integer in 1..64");
  expect_error("", {"dds.domain=230", "dds.domains=4"}, "dds.domains = 4: must be an integer in 1..3");
  expect_error("", {"bridge.http=localhost"}, "bridge.http = 'localhost': must be HOST:PORT");
  // Arrivals drawn in a tick (agent.lambda_in·|D|·agent.dt) at most 10⁵, whatever the queue: an
  // influx of 1e300 hung the arena in its loop over the arrivals.
  expect_error("", {"agent.lambda_in=1e300"}, "agent.lambda_in = 1e+300: must be <= 1105242.66");
  expect_error("", {"agent.lambda_in=1e300"}, "at most 100000 arrivals expected per tick (agent.dt = 0.03 s)");
  // With an endless queue every arrival is a robot for the rest of the run: at most 10⁷ of them
  // (agent.lambda_in·|D|·run.duration). A year of the default influx is refused that way...
  expect_error("", {"arena.queue=endless", "run.duration=2e8"}, "agent.lambda_in = 0.02: must be <= 0.01657");
  expect_error("", {"arena.queue=endless", "run.duration=2e8"},
               "run.duration = 2e+08 s and arena.queue = endless: 12063715.7");
  // ... but not with a finite queue, whose arrivals beyond its robots are dropped: 10⁶ robots in
  // the kinetic world for the default 1,200 s with the controller's default λ_in (it was refused).
  EXPECT_NO_THROW(parse("", {"run.duration=2e8"}));
  EXPECT_NO_THROW(parse("", {"arena.encounter_model=kinetic", "arena.shape=rectangle", "arena.width=790",
                             "arena.height=790", "arena.robots_inside=1000000", "arena.robots_waiting=0",
                             "run.duration=1200"}));
  expect_error("", {"arena.semi_axis_x=2e6"}, "arena.semi_axis_x = 2000000: must be <= 1000000 m");
  expect_error("", {"dds.prefix=a//b"}, "dds.prefix = 'a//b'");
  expect_error("", {"dds.security=yes"}, "dds.security = 'yes': must be on or off");
  expect_error("", {"dds.security=on"}, "dds.security_dir = '': must be a directory made by");
  // A profile that is missing or a directory: the path and what it must be (it said "no such
  // file" for a directory).
  const std::string dir = ::testing::TempDir();
  expect_error("", {"dds.profile=" + dir},
               "dds.profile = '" + dir + "': must be an existing file (a vendor XML");
  expect_error("", {"dds.profile=/nonexistent/p.xml"},
               "dds.profile = '/nonexistent/p.xml': must be an existing file");
}

TEST(ScenarioLoader, ANameOutsideAnEnumsTableListsTheNames) {
  expect_error("", {"arena.shape=circle"}, "arena.shape = 'circle': must be one of ellipse, rectangle");
  expect_error("", {"arena.encounter_model=ballistic"},
               "arena.encounter_model = 'ballistic': must be one of physical, kinetic");
  expect_error("", {"arena.queue=lifo"}, "arena.queue = 'lifo': must be one of finite, endless");
  expect_error("", {"arena.influx=bursty"}, "arena.influx = 'bursty': must be one of steady, poisson");
  expect_error("", {"dds.vendor=opensplice"},
               "dds.vendor = 'opensplice': must be one of fastdds, cyclonedds, inmemory");
  expect_error("", {"run.agent_timeout=10", "run.agent_hang_timeout=9"},
               "run.agent_hang_timeout = 9: must be >= run.agent_timeout (10 wall s)");
}

TEST(ScenarioKeys, TheKeysAreTheSerializedMembersInFileOrder) {
  const auto keys = known_keys();
  // 52 with agent.missed_onsets, agent.false_onsets, arena.missed_onsets, arena.false_onsets
  // (issue 14); 56 with arena.external_robots, external_frozen_after, external_lost_after and
  // external_max_speed (issue 15); 58 with run.plans and run.plan_horizon (issue 13); 59 with
  // run.recorders (issue 16); 60 with run.agent_hang_timeout (issue 13); 61 with dds.domains
  // (issue 13); 62 with arena.retreat_unblock.
  ASSERT_EQ(keys.size(), 62u);
  EXPECT_EQ(keys.front(), "name");
  EXPECT_EQ(keys[2], "model.lambda_p");
  EXPECT_EQ(keys[15], "arena.encounter_model");
  EXPECT_EQ(keys.back(), "bridge.http");
}

TEST(ScenarioJson, EveryShippedScenarioGoesToJsonAndBackUnchanged) {
  const auto files = shipped();
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const auto s = load(f);
    const auto again = parse_json(dump_json(s));
    EXPECT_EQ(dump(again), dump(s));
  }
}

TEST(ScenarioJson, JsonIsValidatedAsYamlIs) {
  const auto expect_json_error = [](const std::string& json, const std::string& expected) {
    try {
      parse_json(json);
      ADD_FAILURE() << "accepted: " << json;
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(expected), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    }
  };
  expect_json_error(R"({"agent": {"window": 90}})",
                    "unknown key 'agent.window' in <json> (allowed in agent: L, dt, K_p, lambda_in, controller, missed_onsets, false_onsets)");
  expect_json_error(R"({"agnet": {"L": 90}})", "unknown key 'agnet'");
  expect_json_error(R"({"model": {"delta": "abc"}})", "model.delta = 'abc': must be a number");
  expect_json_error(R"({"arena": {"robots_inside": 2.5}})",
                    "arena.robots_inside = '2.5': must be a whole number in 0..4294967295");
  expect_json_error(R"({"arena": {"robots_inside": -1}})",
                    "arena.robots_inside = '-1': must be a whole number in 0..4294967295");
  expect_json_error(R"({"arena": {"shape": "circle"}})", "arena.shape = 'circle': must be one of ellipse, rectangle");
  expect_json_error(R"({"dds": {"security": "yes"}})", "dds.security = 'yes': must be on or off");
  expect_json_error(R"({"model": {"delta": -0.1}})", "model.delta = -0.1: must be > 0");
  expect_json_error(R"({"model": [1, 2]})", "model in <json>: must be a mapping");
  expect_json_error(R"({"model": {"delta": )", "<json>: malformed JSON");
}

TEST(ScenarioJson, JsonAndYamlGiveTheSameScenarioForTheSameValues) {
  const auto from_yaml = parse("seed: 7\nagent: {dt: 0.05}\narena: {shape: rectangle, queue: endless}\nrun: {mode: realtime}\n");
  const auto from_json = parse_json(
      R"({"seed": 7, "agent": {"dt": 0.05}, "arena": {"shape": "rectangle", "queue": "endless"}, "run": {"mode": "realtime"}})");
  EXPECT_EQ(dump(from_json), dump(from_yaml));
  EXPECT_EQ(from_json.run.mode, RunMode::realtime);
  EXPECT_DOUBLE_EQ(from_json.arena.tick_dt, 0.05);
}

TEST(ScenarioLoader, MalformedYamlNamesTheLine) {
  expect_error("model:\n  delta: [0.1\n", {}, "<text>: malformed YAML at line");
}

TEST(ScenarioLoader, AMissingFileIsNamed) {
  try {
    load("/nonexistent/scenario.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "--scenario '/nonexistent/scenario.yaml': cannot read the file (a YAML scenario)");
  }
}

}  // namespace
}  // namespace retreat::scenario
