// retreat-agent as a real process over each DDS vendor: a scripted arena (this test) publishes
// frames with known onsets and checks every decision and status the agent publishes against the
// same algorithm run in this process with the same seed.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using testing::ChildProcess;
using testing::eventually;

/// This test's name as a file name part (parameterised names contain '/').
std::string tag_of_test() {
  std::string tag = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::replace(tag.begin(), tag.end(), '/', '_');
  return tag;
}

struct Vendor {
  const char* name;
  int domain_base;  // the first of the vendor's four ids (agent_program block, domains.hpp)
};

class AgentProgram : public ::testing::TestWithParam<Vendor> {
 protected:
  void SetUp() override {
    const auto vendors = transport::dds_vendors();
    if (std::find(vendors.begin(), vendors.end(), GetParam().name) == vendors.end()) {
      GTEST_SKIP() << GetParam().name << " is not built";
    }
  }

  /// @p extra: more sections; @p run: more keys of `run` (a scenario gives each section once).
  std::string write_scenario(const std::string& tag, const std::string& extra, const std::string& run = "") {
    const std::string path = ::testing::TempDir() + "/agent_program_" + tag + "_" + GetParam().name + ".yaml";
    std::ofstream(path) << "name: agent-program-test\nseed: 7\n"
                        << "agent: {L: 0.3, dt: 0.03, K_p: 0.03, lambda_in: 0.02}\n"
                        << "run: {status_period: 0.09" << run << "}\n" << extra;
    return path;
  }

  ChildProcess start_agent(const std::string& scenario, int domain, std::uint32_t robot) {
    return ChildProcess({RETREAT_AGENT_BIN, "--robot-id", std::to_string(robot), "--scenario", scenario,
                         "--dds", GetParam().name, "--domain", std::to_string(domain)},
                        ::testing::TempDir() + "/agent_program_" + tag_of_test() + ".log");
  }
};

/// The scripted arena side: one participant with the agent's frame writer and the readers of
/// its decision and status topics.
struct ScriptedArena {
  ScriptedArena(const char* vendor, int domain, std::uint32_t robot)
      : transport(transport::make_transport(vendor, {domain, "scripted-arena", "retreat:arena", ""})),
        frames(transport->create_writer<wire::ProximityFrame>(
            {wire::proximity_topic("retreat", robot), transport::QosIntent::control()})),
        decisions(transport->create_reader<wire::Decision>(
            {wire::decision_topic("retreat", robot), transport::QosIntent::control()})),
        statuses(transport->create_reader<wire::AgentStatus>(
            {wire::agent_status_topic("retreat"), transport::QosIntent::state()})) {}

  bool matched() { return frames.matched_count() > 0 && decisions.matched_count() > 0; }

  /// Sends a frame and waits for the decision answering its tick. Like the arena in lockstep,
  /// it sends the frame again when no answer came within 300 ms (a sample written while the
  /// two sides are still discovering each other can be missed); `resends` counts those.
  std::optional<wire::Decision> exchange(const wire::ProximityFrame& f) {
    frames.write(f);
    for (int attempt = 0; attempt < 30; ++attempt) {
      if (auto d = await_decision(f.tick, 300ms)) return d;
      frames.write(f);
      ++resends;
    }
    return std::nullopt;
  }

  std::optional<wire::Decision> await_decision(std::int64_t tick, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      transport->wait(20ms);
      for (const auto& d : decisions.take()) received.push_back(d);
      for (const auto& s : statuses.take()) status_log.push_back(s);
      for (const auto& d : received) {
        if (d.tick == tick) return d;
      }
    }
    return std::nullopt;
  }

  std::unique_ptr<transport::Transport> transport;
  transport::Writer<wire::ProximityFrame> frames;
  transport::Reader<wire::Decision> decisions;
  transport::Reader<wire::AgentStatus> statuses;
  std::vector<wire::Decision> received;
  std::vector<wire::AgentStatus> status_log;
  int resends = 0;
};

wire::ProximityFrame frame(std::uint32_t robot, std::int64_t tick, std::uint32_t onsets,
                           wire::Phase phase = wire::Phase::inside) {
  return {robot, tick, 0.03 * static_cast<double>(tick), phase, onsets > 0, onsets};
}

TEST_P(AgentProgram, AnswersEveryFrameWithTheDecisionTheAlgorithmTakesForTheSameSeed) {
  const int domain = GetParam().domain_base;
  const std::uint32_t robot = 2;
  const auto path = write_scenario("reference", "");
  const auto s = scenario::load(path);
  ScriptedArena arena(GetParam().name, domain, robot);
  auto agent_process = start_agent(path, domain, robot);
  ASSERT_TRUE(eventually([&] { return arena.matched(); }, retreat::testing::hang_ceiling)) << "agent never matched";

  // The reference: the same algorithm, the same parameters, the same seed.
  agent::RetreatAgent reference(robot, s.model, s.agent, agent::make_controller("paper"),
                                seed_for(s.seed, robot, Stream::agent_decision));
  // Onsets: 2 on every third tick, a high density, so that the coin is flipped with p > 0.
  std::vector<std::int64_t> retreat_ticks;
  for (std::int64_t tick = 0; tick < 200; ++tick) {
    const auto f = frame(robot, tick, tick % 3 == 0 ? 2 : 0);
    const auto expected = reference.on_frame({f.tick, f.time, agent::RobotPhase::inside, f.in_contact, f.new_onsets, robot});
    const auto got = arena.exchange(f);
    ASSERT_TRUE(got.has_value()) << "no decision for tick " << tick;
    ASSERT_EQ(got->robot_id, robot);
    ASSERT_EQ(got->retreat, expected.retreating) << "tick " << tick;
    if (got->retreat) retreat_ticks.push_back(tick);
    if (expected.retreating) break;
  }
  // The statuses carry the reference's estimate.
  ASSERT_TRUE(eventually([&] {
    arena.await_decision(-1, 50ms);
    return !arena.status_log.empty() && arena.status_log.back().lambda_hat > 0;
  }, retreat::testing::hang_ceiling));
  const auto last = arena.status_log.back();
  EXPECT_EQ(last.robot_id, robot);
  EXPECT_GT(last.onsets_in_window, 0u);
  EXPECT_EQ(agent_process.stop(), 0) << "SIGTERM must end the agent cleanly";
}

TEST_P(AgentProgram, DecidesEveryDtOfTheFramesClockWhenFramesArriveInBursts) {
  // Real time: frames come every 7 ticks (late, in bursts); the agent must still take one
  // decision step per dt of the frames' clock, exactly as the algorithm does in this process.
  const int domain = GetParam().domain_base + 3;
  const std::uint32_t robot = 5;
  const auto path = write_scenario("bursts", "arena: {robots_inside: 6}\n", ", mode: realtime");
  const auto s = scenario::load(path);
  ScriptedArena arena(GetParam().name, domain, robot);
  auto agent_process = start_agent(path, domain, robot);
  ASSERT_TRUE(eventually([&] { return arena.matched(); }, retreat::testing::hang_ceiling));
  agent::RetreatAgent reference(robot, s.model, s.agent, agent::make_controller("paper"),
                                seed_for(s.seed, robot, Stream::agent_decision));
  // Far above λ*, ε is close to K_p (0.03/s), so the chance per step is about K_p·dt = 9e-4:
  // within 30,000 steps an agent stays with probability (1 − 9e-4)^30000 ≈ 2e-12. (Seed 7's
  // agent leaves at tick 2,023; the loop stops there.)
  bool retreated = false;
  for (std::int64_t tick = 0; tick < 30000 && !retreated; tick += 7) {
    const auto f = frame(robot, tick, 4);
    const auto expected = reference.on_frame({f.tick, f.time, agent::RobotPhase::inside, f.in_contact, f.new_onsets, robot});
    const auto got = arena.exchange(f);
    ASSERT_TRUE(got.has_value()) << "tick " << tick;
    ASSERT_EQ(got->retreat, expected.retreating) << "tick " << tick;
    retreated = got->retreat;
  }
  EXPECT_TRUE(retreated) << "4 onsets per 7 ticks is far above λ*: the agent should have left";
  EXPECT_GT(reference.status().steps, 0u);
  EXPECT_EQ(agent_process.stop(), 0);
}

TEST_P(AgentProgram, RetreatsAtExactlyTheFirstDecisionTickWhenEpsilonDtIsOne) {
  const int domain = GetParam().domain_base + 1;
  const std::uint32_t robot = 1;
  // K_p = 1000: ε(λ̂)·dt = (λ_in + K_p(λ̂ − λ*))/λ̂ · dt ≥ 1 for any λ̂ above λ*, so the
  // first coin is certain. L = 0.3 s, dt = 0.03 s: the first decision step is k = 10.
  const auto path = write_scenario("forced", "");
  ScriptedArena arena(GetParam().name, domain, robot);
  ChildProcess agent_process({RETREAT_AGENT_BIN, "--robot-id", std::to_string(robot), "--scenario", path,
                              "--dds", GetParam().name, "--domain", std::to_string(domain), "--set", "agent.K_p=1000"},
                             ::testing::TempDir() + "/agent_forced.log");
  ASSERT_TRUE(eventually([&] { return arena.matched(); }, retreat::testing::hang_ceiling));
  for (std::int64_t tick = 0; tick <= 12; ++tick) {
    const auto d = arena.exchange(frame(robot, tick, 3));  // 3 onsets per tick: λ̂ far above λ*
    ASSERT_TRUE(d.has_value()) << "tick " << tick;
    EXPECT_EQ(d->retreat, tick >= 10) << "tick " << tick;
  }
  // The robot drives out and departs: the agent exits 0 by itself.
  ASSERT_TRUE(arena.exchange(frame(robot, 13, 0, wire::Phase::retreating)).has_value());
  arena.frames.write(frame(robot, 14, 0, wire::Phase::departed));
  const auto code = agent_process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the agent did not exit after its robot departed";
  EXPECT_EQ(*code, 0);
}

TEST_P(AgentProgram, DropsAndCountsFramesForAnotherRobotBackwardsOrDuplicatedNeverActingOnThem) {
  const int domain = GetParam().domain_base + 2;
  const std::uint32_t robot = 3;
  const auto path = write_scenario("drops", "");
  ScriptedArena arena(GetParam().name, domain, robot);
  auto agent_process = start_agent(path, domain, robot);
  ASSERT_TRUE(eventually([&] { return arena.matched(); }, retreat::testing::hang_ceiling));
  for (std::int64_t tick = 0; tick < 5; ++tick) ASSERT_TRUE(arena.exchange(frame(robot, tick, 1)).has_value());
  arena.frames.write(frame(4, 5, 1));           // another robot's frame on robot 3's topic
  arena.frames.write(frame(robot, 2, 1));       // tick going backwards
  arena.frames.write(frame(robot, 4, 1));       // duplicated tick
  auto nan = frame(robot, 6, 1);
  nan.time = std::nan("");
  arena.frames.write(nan);                      // invalid time
  const auto next = arena.exchange(frame(robot, 9, 0));
  ASSERT_TRUE(next.has_value());
  // Decisions only for the accepted ticks 0..4 and 9, none for the dropped frames.
  std::set<std::int64_t> answered;
  for (const auto& d : arena.received) answered.insert(d.tick);
  EXPECT_EQ(answered, (std::set<std::int64_t>{0, 1, 2, 3, 4, 9}));
  // The next status reports the four dropped frames (plus any re-sends, which the agent sees as
  // duplicated ticks and answers again without acting on them).
  ASSERT_TRUE(arena.exchange(frame(robot, 12, 0)).has_value());
  const auto expected_drops = static_cast<std::uint64_t>(4 + arena.resends);
  ASSERT_TRUE(eventually([&] {
    arena.await_decision(-1, 20ms);
    return !arena.status_log.empty() && arena.status_log.back().frames_dropped == expected_drops;
  }, retreat::testing::hang_ceiling)) << "last status reports " << (arena.status_log.empty() ? 0 : arena.status_log.back().frames_dropped)
          << ", expected " << expected_drops;
  EXPECT_EQ(agent_process.stop(), 0);
}

void PrintTo(const Vendor& v, std::ostream* os) { *os << v.name; }

INSTANTIATE_TEST_SUITE_P(Vendors, AgentProgram,
                         ::testing::Values(Vendor{"fastdds", testing::domains::agent_program.at(0)}, Vendor{"cyclonedds", testing::domains::agent_program_cyclonedds.first}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(AgentProgramBadInput, EachBadValueGivesOneLineNamingItAndExitCodeTwo) {
  const std::string dir = ::testing::TempDir();
  const std::string good = dir + "/agent_bad_input.yaml";
  std::ofstream(good) << "name: bad-input\n";
  const std::string malformed = dir + "/agent_malformed.yaml";
  std::ofstream(malformed) << "agent: {L: [unclosed\n";
  struct Case {
    std::vector<std::string> args;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {{"--robot-id", "0", "--scenario", good, "--set", "model.delta=-0.1"}, "model.delta = -0.1"},
      {{"--robot-id", "0", "--scenario", good, "--set", "model.v=0"}, "model.v = 0"},
      {{"--robot-id", "0", "--scenario", good, "--set", "agent.L=-3"}, "agent.L = -3"},
      {{"--robot-id", "0", "--scenario", good, "--set", "agent.dt=0"}, "agent.dt = 0"},
      {{"--robot-id", "0", "--scenario", good, "--set", "agent.dt=100"}, "agent.dt = 100"},
      {{"--robot-id", "0", "--scenario", good, "--set", "model.C=0"}, "model.C = 0"},
      {{"--robot-id", "0", "--scenario", good, "--set", "model.lambda_p=-1"}, "model.lambda_p = -1"},
      {{"--robot-id", "0", "--scenario", good, "--set", "model.lambda_d=0"}, "model.lambda_d = 0"},
      {{"--robot-id", "0", "--scenario", good, "--set", "agent.controller=bang-bang"}, "agent.controller = 'bang-bang'"},
      {{"--robot-id", "0", "--scenario", good, "--set", "agent.colour=red"}, "unknown key 'agent.colour'"},
      {{"--robot-id", "0", "--scenario", malformed}, "malformed YAML"},
      {{"--robot-id", "0", "--scenario", dir + "/missing.yaml"}, "missing.yaml"},
      {{"--robot-id", "99", "--scenario", good}, "--robot-id 99"},
      {{"--robot-id", "-1", "--scenario", good}, "--robot-id '-1': must be a whole number in 0..4294967295"},
      {{"--robot-id", "0x1", "--scenario", good}, "--robot-id '0x1': must be a whole number"},
      {{"--robot-id", "0", "--scenario", good, "--dds", "opensplice"}, "dds.vendor = 'opensplice'"},
      {{"--robot-id", "0", "--scenario", good, "--domain", "500"}, "--domain '500': must be a whole number in 0..232"},
      {{"--robot-id", "0", "--scenario", good, "--set", "dds.profile=/nonexistent.xml"}, "dds.profile = '/nonexistent.xml'"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> argv = {RETREAT_AGENT_BIN};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const std::string log = dir + "/agent_bad_input.log";
    const auto [code, text] = testing::run_to_exit(argv, log);
    EXPECT_EQ(code, 2) << c.expected;
    EXPECT_NE(text.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << "not one line: " << text;
  }
}

#if defined(RETREAT_AGENT_FASTDDS_BIN) && defined(RETREAT_AGENT_CYCLONEDDS_BIN)
// retreat-agent-fastdds and retreat-agent-cyclonedds (what retreat-launch starts when they are
// beside retreat-agent) have one DDS vendor linked: the other vendor is bad input for them, one
// line naming it and what this program allows. (That they serve a swarm, and interoperate with
// the other vendor's program, is LaunchRuns' mixed run.)
TEST(SingleVendorAgent, RefusesTheOtherVendorInOneLineNamingTheVendorsItHas) {
  const std::string dir = ::testing::TempDir();
  const std::string scenario = dir + "/single_vendor.yaml";
  std::ofstream(scenario) << "name: single-vendor\n";
  struct Case {
    const char* program;
    const char* own;
    const char* other;
  };
  for (const auto& c : {Case{RETREAT_AGENT_FASTDDS_BIN, "fastdds", "cyclonedds"},
                        Case{RETREAT_AGENT_CYCLONEDDS_BIN, "cyclonedds", "fastdds"}}) {
    const auto [code, text] = testing::run_to_exit(
        {c.program, "--robot-id", "0", "--scenario", scenario, "--dds", c.other, "--domain",
         std::to_string(testing::domains::agent_program.at(0))},
        dir + "/single_vendor_" + c.own + ".log");
    EXPECT_EQ(code, 2) << c.program << ": " << text;
    EXPECT_NE(text.find(std::string("'") + c.other + "'"), std::string::npos) << text;
    EXPECT_NE(text.find(std::string("must be one of ") + c.own + ", inmemory"), std::string::npos)
        << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << "not one line: " << text;
  }
}
#endif

}  // namespace
}  // namespace retreat
