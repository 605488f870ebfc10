// A real robot's side over DDS: retreat-robot-example (C, on the C robot link only) and the C++
// RobotLink, each against an unmodified retreat-agent process, over each vendor. Also the agent's
// field behaviour: a restart that resumes from its journal, run.startup_timeout, bad journals.
// DDS domain ids: the robot_link blocks of retreat/testing/domains.hpp; the built-in loopback-only
// settings.

#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/robot/robot_link.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"
#include "retreat/transport/factory.hpp"

namespace retreat {
namespace {

using namespace std::chrono_literals;
using testing::ChildProcess;
using testing::eventually;
using testing::hang_ceiling;

struct Vendor {
  const char* name;
  int domain_base;  // the first of the vendor's five ids
};

void PrintTo(const Vendor& v, std::ostream* os) { *os << v.name; }

/// One row of the example robot's --log, or one journalled frame.
struct Row {
  std::int64_t tick = 0;
  double time = 0.0;
  unsigned phase = 0;
  int in_contact = 0;
  std::uint32_t onsets = 0;
  int retreat = 0;  ///< the robot's log only
};

/// The rows of a CSV file (the example's log has a header line, a journal a '#' line).
std::vector<Row> read_rows(const std::string& path, bool with_retreat) {
  std::ifstream in(path);
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 't') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    Row r;
    fields >> r.tick >> r.time >> r.phase >> r.in_contact >> r.onsets;
    if (with_retreat) fields >> r.retreat;
    rows.push_back(r);
  }
  return rows;
}

class RobotLinkOverDds : public ::testing::TestWithParam<Vendor> {
 protected:
  void SetUp() override {
    const auto vendors = transport::dds_vendors();
    if (std::find(vendors.begin(), vendors.end(), GetParam().name) == vendors.end()) {
      GTEST_SKIP() << GetParam().name << " is not built";
    }
    tag_ = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::replace(tag_.begin(), tag_.end(), '/', '_');
  }
  void TearDown() override {
    for (const auto& f : files_) std::remove(f.c_str());
  }

  /// A temporary file of this test (removed at the end).
  std::string file(const std::string& name) {
    files_.push_back(::testing::TempDir() + "/robot_link_" + tag_ + "_" + name);
    return files_.back();
  }

  /// L = 3 s, dt = 0.1 s, `paper`; @p extra appends YAML.
  std::string write_scenario(int domain, const std::string& mode, const std::string& extra = "") {
    const auto path = file("scenario.yaml");
    std::ofstream(path) << "name: robot-link-test\nseed: 11\n"
                        << "agent: {L: 3, dt: 0.1, K_p: 0.5, lambda_in: 0}\n"
                        << "run: {mode: " << mode << ", status_period: 0.1}\n"
                        << "dds: {vendor: " << GetParam().name << ", domain: " << domain << "}\n" << extra;
    return path;
  }

  ChildProcess start_agent(const std::string& scenario, std::uint32_t robot, const std::string& journal,
                           const std::string& log_name = "agent.log") {
    std::vector<std::string> argv{RETREAT_AGENT_BIN, "--robot-id", std::to_string(robot), "--scenario", scenario};
    if (!journal.empty()) {
      argv.push_back("--journal");
      argv.push_back(journal);
    }
    return ChildProcess(argv, file(log_name));
  }

  /// The decisions of `paper` for @p scenario's robot @p robot on @p rows, in this process.
  agent::RetreatAgent reference(const std::string& scenario, std::uint32_t robot) {
    const auto s = scenario::load(scenario);
    return agent::RetreatAgent(robot, s.model, s.agent, agent::make_controller("paper"),
                               seed_for(s.seed, robot, Stream::agent_decision));
  }

  static agent::Observation observation(const Row& r, std::uint32_t robot) {
    return {r.tick, r.time, static_cast<agent::RobotPhase>(r.phase), r.in_contact != 0, r.onsets, robot};
  }

  std::string tag_;
  std::vector<std::string> files_;
};

TEST_P(RobotLinkOverDds, TheExampleRobotInLockstepGetsExactlyTheDecisionsOfTheAlgorithm) {
  const int domain = GetParam().domain_base;
  const std::uint32_t robot = 1;
  const auto scenario = write_scenario(domain, "lockstep");
  auto agent_process = start_agent(scenario, robot, "");
  const auto log = file("robot.csv");
  const auto [code, output] = testing::run_to_exit(
      {RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "1", "--scenario", scenario, "--rate", "10", "--jitter", "0.3",
       "--onset-rate", "3", "--miss", "0.1", "--false-rate", "0.2", "--seed", "5", "--log", log},
      file("robot.log"));
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("departed"), std::string::npos) << output;
  const auto rows = read_rows(log, true);
  ASSERT_GT(rows.size(), 30u) << "at least L = 3 s of frames at 10 Hz";
  auto expected = reference(scenario, robot);
  std::int64_t retreat_tick = -1;
  for (const auto& r : rows) {
    const auto e = expected.on_frame(observation(r, robot));
    ASSERT_EQ(e.verdict, agent::FrameVerdict::accepted) << "tick " << r.tick;
    // The robot's state after each frame's answer is the algorithm's after that frame.
    ASSERT_EQ(r.retreat != 0, e.retreating) << "tick " << r.tick;
    if (e.retreat_now) retreat_tick = r.tick;
  }
  EXPECT_GT(retreat_tick, 0) << "the robot retreated";
  EXPECT_EQ(rows.back().phase, 3u) << "the robot drove out and departed";
  const auto agent_code = agent_process.wait_for(hang_ceiling);
  ASSERT_TRUE(agent_code.has_value()) << "the agent did not exit after its robot departed";
  EXPECT_EQ(*agent_code, 0);
}

TEST_P(RobotLinkOverDds, TheExampleRobotInRealTimeAt10HzWithJitterRetreatsWhereTheAlgorithmDoes) {
  // Real time: the robot's own clock and loop (10 Hz ± 30 %), answers taken as they come. What the
  // agent acted on is in its journal; the algorithm on those frames decides at tick T, and the
  // robot learns it at T or a little later, never before.
  const int domain = GetParam().domain_base + 1;
  const std::uint32_t robot = 2;
  const auto scenario = write_scenario(domain, "realtime");
  const auto journal = file("agent.journal");
  auto agent_process = start_agent(scenario, robot, journal);
  const auto log = file("robot.csv");
  const auto [code, output] = testing::run_to_exit(
      {RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "2", "--scenario", scenario, "--rate", "10", "--jitter", "0.3",
       "--onset-rate", "4", "--seed", "6", "--log", log},
      file("robot.log"));
  ASSERT_EQ(code, 0) << output;
  const auto agent_code = agent_process.wait_for(hang_ceiling);
  ASSERT_TRUE(agent_code.has_value()) << "the agent did not exit after its robot departed";
  EXPECT_EQ(*agent_code, 0);
  const auto rows = read_rows(log, true);
  const auto seen = read_rows(journal, false);
  ASSERT_FALSE(seen.empty());
  // Every frame the agent accepted is the robot's frame of that tick, field for field, and from
  // its first frame on it lost none (reliable, in order).
  std::map<std::int64_t, Row> by_tick;
  for (const auto& r : rows) by_tick[r.tick] = r;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const auto& s = seen[i];
    ASSERT_TRUE(by_tick.count(s.tick)) << "tick " << s.tick;
    const auto& r = by_tick[s.tick];
    EXPECT_EQ(s.time, r.time);
    EXPECT_EQ(s.phase, r.phase);
    EXPECT_EQ(s.in_contact, r.in_contact);
    EXPECT_EQ(s.onsets, r.onsets);
    if (i > 0) {
      EXPECT_EQ(s.tick, seen[i - 1].tick + 1);
    }
  }
  EXPECT_EQ(seen.back().tick, rows.back().tick) << "the agent saw the departed frame";
  auto expected = reference(scenario, robot);
  std::int64_t decided = -1;
  for (const auto& s : seen) {
    if (expected.on_frame(observation(s, robot)).retreat_now) decided = s.tick;
  }
  ASSERT_GE(decided, 0) << "the algorithm retreats on these frames";
  const auto first = std::find_if(rows.begin(), rows.end(), [](const Row& r) { return r.retreat != 0; });
  ASSERT_NE(first, rows.end()) << "the robot was told to retreat";
  EXPECT_GE(first->tick, decided) << "a robot cannot learn a decision before it is taken";
}

TEST_P(RobotLinkOverDds, ARestartedAgentResumesItsWindowFromTheJournalAndDecidesAsIfNeverStopped) {
  const int domain = GetParam().domain_base + 2;
  const std::uint32_t robot = 3;
  const auto scenario = write_scenario(domain, "lockstep");
  const auto journal = file("agent.journal");
  robot::RobotLink link(robot::link_options(scenario::load(scenario), robot));
  // The test watches the agent's status with a participant of its own, as an observer does.
  auto observer = transport::make_transport(GetParam().name, {domain, "observer", "test:observer", ""});
  auto statuses = observer->create_reader<wire::AgentStatus>(
      {wire::agent_status_topic("retreat"), transport::QosIntent::state()});
  auto expected = reference(scenario, robot);
  auto blind = reference(scenario, robot);  // what an agent restarted without its journal would know
  // A frame every 0.1 s from t = 0.05 s; one onset every third frame.
  auto frame_of = [](std::int64_t tick) {
    return Row{tick, 0.05 + 0.1 * static_cast<double>(tick), 1, tick % 3 == 0, tick % 3 == 0 ? 1u : 0u, 0};
  };
  std::map<std::int64_t, agent::AgentSnapshot> expected_status;
  std::map<std::int64_t, agent::AgentSnapshot> blind_status;
  auto exchange = [&](std::int64_t tick) {
    const auto r = frame_of(tick);
    const auto e = expected.on_frame(observation(r, robot));
    expected_status[tick] = expected.status();
    const auto sent = link.report(r.time, wire::Phase::inside, r.in_contact != 0, r.onsets);
    EXPECT_EQ(sent, tick);
    EXPECT_TRUE(link.await_answer(hang_ceiling)) << "no answer for tick " << tick;
    EXPECT_EQ(link.retreat(), e.retreating) << "tick " << tick;
    return e.retreating;
  };
  {
    auto first = start_agent(scenario, robot, journal, "agent_first.log");
    ASSERT_TRUE(link.wait_for_agent(hang_ceiling));
    for (std::int64_t tick = 0; tick < 20; ++tick) ASSERT_FALSE(exchange(tick)) << "tick " << tick;
    first.signal(SIGKILL);  // mid-window: L = 3 s is 30 frames
    ASSERT_TRUE(first.wait_for(hang_ceiling).has_value());
  }
  const auto second_log = file("agent_second.log");
  ChildProcess second({RETREAT_AGENT_BIN, "--robot-id", std::to_string(robot), "--scenario", scenario,
                       "--journal", journal}, second_log);
  bool retreated = false;
  std::int64_t tick = 20;
  for (; tick < 3000 && !retreated; ++tick) {
    retreated = exchange(tick);
    blind.on_frame(observation(frame_of(tick), robot));
    blind_status[tick] = blind.status();
  }
  EXPECT_TRUE(retreated) << "3.3 onsets/s is far above λ*: the robot should be told to leave";
  EXPECT_GT(tick, 31) << "decided after the first full window, which spans the restart";
  // The resumed agent's window covers the frames before the restart: its statuses after the
  // restart carry the uninterrupted agent's counts, which a blind restart would not.
  std::map<std::int64_t, wire::AgentStatus> got;
  ASSERT_TRUE(eventually([&] {
    observer->wait(20ms);
    for (const auto& st : statuses.take()) got[st.tick] = st;
    return std::any_of(got.begin(), got.end(), [](const auto& g) { return g.second.retreating; });
  }, hang_ceiling)) << "no status saying retreating";
  int compared = 0;
  for (const auto& [t, st] : got) {
    if (t < 20) continue;
    ++compared;
    EXPECT_EQ(st.onsets_in_window, expected_status[t].onsets_in_window) << "tick " << t;
    EXPECT_EQ(st.lambda_hat, expected_status[t].lambda_hat) << "tick " << t;
    // Until tick 48 the uninterrupted window reaches back before tick 20, to an onset a blind
    // agent never saw.
    if (t <= 48) {
      EXPECT_NE(st.onsets_in_window, blind_status[t].onsets_in_window) << "tick " << t;
    }
  }
  EXPECT_GT(compared, 0);
  const auto log = testing::read_file(second_log);
  EXPECT_NE(log.find("resumed from the journal"), std::string::npos) << log;
  // The robot drives out and departs: the resumed agent exits by itself.
  ASSERT_TRUE(link.report(0.05 + 0.1 * static_cast<double>(tick), wire::Phase::departed, false, 0).has_value());
  const auto code = second.wait_for(hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the resumed agent did not exit after its robot departed";
  EXPECT_EQ(*code, 0);
}

TEST_P(RobotLinkOverDds, RefusesAndCountsReportsWithABadClockAndCarriesTheirOnsets) {
  const int domain = GetParam().domain_base + 3;
  const auto scenario = write_scenario(domain, "lockstep");
  auto agent_process = start_agent(scenario, 4, "");
  robot::RobotLink link(robot::link_options(scenario::load(scenario), 4));
  ASSERT_TRUE(link.wait_for_agent(hang_ceiling));
  ASSERT_EQ(link.report(1.0, wire::Phase::inside, false, 0), 0);
  ASSERT_TRUE(link.await_answer(hang_ceiling));
  EXPECT_FALSE(link.report(0.5, wire::Phase::inside, true, 2).has_value());  // the clock went back
  EXPECT_NE(link.refused_reason().find("went back"), std::string::npos) << link.refused_reason();
  EXPECT_FALSE(link.report(std::nan(""), wire::Phase::inside, true, 1).has_value());
  EXPECT_FALSE(link.report(-1.0, wire::Phase::inside, true, 1).has_value());
  EXPECT_FALSE(link.report(1.5, static_cast<wire::Phase>(7), true, 1).has_value());
  EXPECT_EQ(link.counters().reports_refused, 4u);
  EXPECT_EQ(link.counters().frames_sent, 1u);
  // The next good report carries the refused reports' 5 onsets and its own 1.
  ASSERT_EQ(link.report(1.1, wire::Phase::inside, true, 1), 1);
  ASSERT_TRUE(link.await_answer(hang_ceiling));
  ASSERT_EQ(link.report(1.2, wire::Phase::departed, false, 0), 2);
  EXPECT_FALSE(link.report(1.3, wire::Phase::inside, false, 0).has_value()) << "nothing after departed";
  const auto code = agent_process.wait_for(hang_ceiling);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 0);
}

TEST_P(RobotLinkOverDds, AnAgentWithNoArenaExitsAfterStartupTimeoutAndABadJournalIsOneLine) {
  const int domain = GetParam().domain_base + 4;
  const auto scenario = write_scenario(domain, "lockstep", "");
  const auto [code, output] = testing::run_to_exit(
      {RETREAT_AGENT_BIN, "--robot-id", "0", "--scenario", scenario, "--set", "run.startup_timeout=2"},
      file("timeout.log"));
  EXPECT_EQ(code, 3) << output;
  EXPECT_NE(output.find("run.startup_timeout = 2 s"), std::string::npos) << output;
  // Another robot's journal: refused at start-up with one line naming the file.
  const auto journal = file("other.journal");
  std::ofstream(journal) << "# retreat-agent journal 1 robot=9 fingerprint=0\n0,0.1,1,0,0\n";
  const auto [bad, said] = testing::run_to_exit(
      {RETREAT_AGENT_BIN, "--robot-id", "0", "--scenario", scenario, "--journal", journal}, file("bad.log"));
  EXPECT_EQ(bad, 2) << said;
  EXPECT_NE(said.find(journal + "' line 1"), std::string::npos) << said;
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
  // A directory: refused in one line naming it (its first read threw std::ios_base::failure).
  const auto directory = std::filesystem::path(journal).parent_path().string();
  const auto [not_file, answer] = testing::run_to_exit(
      {RETREAT_AGENT_BIN, "--robot-id", "0", "--scenario", scenario, "--journal", directory}, file("dir.log"));
  EXPECT_EQ(not_file, 2) << answer;
  EXPECT_NE(answer.find("--journal '" + directory + "' cannot be read as a file"), std::string::npos) << answer;
  EXPECT_EQ(std::count(answer.begin(), answer.end(), '\n'), 1) << answer;
}

INSTANTIATE_TEST_SUITE_P(Vendors, RobotLinkOverDds,
                         ::testing::Values(Vendor{"cyclonedds", testing::domains::robot_link_cyclonedds.first},
                                           Vendor{"fastdds", testing::domains::robot_link_fastdds.first}),
                         [](const ::testing::TestParamInfo<Vendor>& v) { return std::string(v.param.name); });

TEST(RobotExample, BadArgumentsAreOneLineAndExitTwo) {
  // Each: the arguments, and what its one line must say. A whole number is decimal digits in its
  // range: "-1", "1.5" and "0x10" used to be read by strtod (0x10 as 16), and a bad one printed
  // two lines, the second not naming the value.
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--robot-id", "x"}, "--robot-id 'x' is not a whole number in [0, 4294967295]"},
      {{"--robot-id", "-1"}, "--robot-id '-1' is not a whole number in [0, 4294967295]"},
      {{"--robot-id", "1.5"}, "--robot-id '1.5' is not a whole number in [0, 4294967295]"},
      {{"--robot-id", "4294967296"}, "--robot-id '4294967296' is not a whole number"},
      {{"--robot-id", "1", "--domain", "0x10"}, "--domain '0x10' is not a whole number in [0, 232]"},
      {{"--robot-id", "1", "--seed", "18446744073709551616"}, "--seed '18446744073709551616' is not a whole number"},
      {{"--robot-id", "1", "--rate", "0"}, "--rate '0' is not a number in [0.1, 1000]"},
      {{"--robot-id", "1", "--dds", "nodds"}, "nodds"},
      {{"--rate", "10"}, "--robot-id is required"},
      {{"--robot-id", "1", "--frobnicate"}, "'--frobnicate': an unknown option"},
      {{"--robot-id"}, "'--robot-id': an unknown option, or one without its value"},
      {{"--robot-id", "1", "--scenario", "/nonexistent.yaml"}, "/nonexistent.yaml"}};
  for (const auto& [args, line] : cases) {
    std::vector<std::string> argv{RETREAT_ROBOT_EXAMPLE_BIN};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto [code, output] = testing::run_to_exit(argv, ::testing::TempDir() + "/robot_example_args.log");
    EXPECT_EQ(code, 2) << line << ": " << output;
    EXPECT_NE(output.find(line), std::string::npos) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << "one line: " << output;
  }
  std::remove((::testing::TempDir() + "/robot_example_args.log").c_str());
}

TEST(RobotExample, AScenarioWithPlansIsRefusedInOneLine) {
  // The shipped scenarios run event-driven lockstep (run.plans: true), which a link does not
  // speak: its agent would answer with plans it never reads. Refused at start, not a hang.
  const std::string scenario = ::testing::TempDir() + "/robot_example_plans.yaml";
  std::ofstream(scenario) << "run:\n  mode: lockstep\n  plans: true\ndds:\n  vendor: cyclonedds\n";
  const auto [code, output] = testing::run_to_exit({RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "1", "--scenario", scenario},
                                                   ::testing::TempDir() + "/robot_example_plans.log");
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("run.plans = true"), std::string::npos) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  std::remove(scenario.c_str());
  std::remove((::testing::TempDir() + "/robot_example_plans.log").c_str());
}

}  // namespace
}  // namespace retreat
