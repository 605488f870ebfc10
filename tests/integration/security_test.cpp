// DDS Security (docs/security.md): the swarm PKI script, secure swarms of real processes over
// real DDS, and what the permissions refuse. Assertions are on exit codes, the run directory's
// summary.json and the transport's own errors, never on log text.
//
// Domain ids of this file: 65..71 (one per test that touches DDS, constants below).

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <stdexcept>
#include <thread>

#include "launch_support.hpp"
#include "retreat/replay/recording.hpp"
#include "retreat/testing/domains.hpp"
#include "retreat/testing/process.hpp"

namespace retreat::launch_test {
namespace {

const std::string pki_script = RETREAT_PKI_SCRIPT;

/// A fresh PKI for robots 0..11, the arena and the bridge under `<dir>/pki` (the script's own
/// tests: everything else shares one PKI, below).
std::string make_pki(const std::string& dir) {
  const auto pki = dir + "/pki";
  const auto [code, output] =
      testing::run_to_exit({"/bin/bash", pki_script, "--out", pki, "--robots", "0-11"}, dir + "/pki.log");
  EXPECT_EQ(code, 0) << output;
  return pki;
}

/// The PKI every secure swarm and permission test uses: made once per test run by the CTest
/// fixture `security_pki` (security.cmake; ctest adds it to any selection of these tests), since
/// making 14 identities costs seconds of openssl, many more on a loaded machine.
std::string shared_pki() {
  const std::string pki = RETREAT_SHARED_PKI;
  if (!std::filesystem::is_regular_file(pki + "/robot_11/permissions.p7s")) {
    ADD_FAILURE() << "no shared PKI in " << pki << ": run these tests with ctest (fixture "
                  << "security_pki), or first: bash " << pki_script << " --out " << pki
                  << " --robots 0-11";
  }
  return pki;
}

/// robotarium-2019 for 120 simulated s (4,000 ticks): long enough that agents retreat (seed 1:
/// seven of them), so the trajectory hash depends on every agent's decisions; 4–12 s of wall time.
/// Per-tick lockstep (the shipped scenario runs plans; a test adds run.plans=true after these):
/// the arena reads every robot's decision topic every tick, where the intruder injects.
std::vector<std::string> run_args(const std::string& vendor, int domain) {
  return {robotarium, "--dds", vendor, "--domain", std::to_string(domain), "--seed", "1",
          "--set", "run.duration=120", "--set", "run.plans=false"};
}
std::vector<std::string> secure(std::vector<std::string> args, const std::string& pki) {
  args.insert(args.end(), {"--set", "dds.security=on", "--set", "dds.security_dir=" + pki});
  return args;
}

/// Runs a swarm to its end and returns its summary.json (empty when the launcher failed).
json run_swarm(const std::string& dir, const std::vector<std::string>& args) {
  std::filesystem::create_directories(dir);
  const auto code = run_launch(dir, args);
  EXPECT_EQ(code, 0) << log_of(dir);
  return read_json(dir + "/run/summary.json");
}

// ---- the PKI script ------------------------------------------------------------------------

TEST(SwarmPki, MakesOneIdentityPerRobotArenaBridgeAndRecorderAndKeepsThemOnASecondRun) {
  const auto dir = fresh_dir("security-pki");
  const auto pki = make_pki(dir);
  for (const auto* file : {"ca.pem", "ca.key", "governance.xml", "governance.p7s"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(pki + "/" + file)) << file;
  }
  std::vector<std::string> identities = {"arena", "bridge", "recorder"};
  for (int r = 0; r < 12; ++r) identities.push_back("robot_" + std::to_string(r));
  for (const auto& id : identities) {
    for (const auto* file : {"cert.pem", "key.pem", "permissions.xml", "permissions.p7s"}) {
      EXPECT_TRUE(std::filesystem::is_regular_file(pki + "/" + id + "/" + file)) << id << "/" << file;
    }
  }
  // Agent 3 may read only its robot's proximity frames and write only its decision (or plan) and status.
  const auto robot3 = testing::read_file(pki + "/robot_3/permissions.xml");
  EXPECT_NE(robot3.find("<subject_name>CN=robot_3,O=retreat,C=ZZ</subject_name>"), std::string::npos);
  EXPECT_NE(robot3.find("<subscribe><topics><topic>retreat/robot_3/proximity</topic></topics></subscribe>"),
            std::string::npos) << robot3;
  EXPECT_NE(robot3.find("<publish><topics><topic>retreat/robot_3/decision</topic>"
                        "<topic>retreat/robot_3/plan</topic><topic>retreat/agent_status</topic></topics></publish>"),
            std::string::npos) << robot3;
  EXPECT_EQ(testing::read_file(pki + "/bridge/permissions.xml").find("<publish>"), std::string::npos);
  // The recorder reads every topic of the swarm and writes none.
  const auto recorder = testing::read_file(pki + "/recorder/permissions.xml");
  EXPECT_EQ(recorder.find("<publish>"), std::string::npos) << recorder;
  for (const auto* topic : {"retreat/robot_*/proximity", "retreat/robot_*/decision", "retreat/robot_*/plan",
                            "retreat/robot_*/tracked_pose", "retreat/arena_telemetry", "retreat/poses",
                            "retreat/agent_status"}) {
    EXPECT_NE(recorder.find(std::string("<topic>") + topic + "</topic>"), std::string::npos) << topic;
  }

  const auto cert = testing::read_file(pki + "/robot_3/cert.pem");
  const auto signed_permissions = testing::read_file(pki + "/robot_3/permissions.p7s");
  const auto ca = testing::read_file(pki + "/ca.pem");
  make_pki(dir);  // idempotent: the same arguments change nothing
  EXPECT_EQ(testing::read_file(pki + "/robot_3/cert.pem"), cert);
  EXPECT_EQ(testing::read_file(pki + "/robot_3/permissions.p7s"), signed_permissions);
  EXPECT_EQ(testing::read_file(pki + "/ca.pem"), ca);
}

TEST(SwarmPki, RefusesBadInputWithOneLineNamingTheValue) {
  const auto dir = fresh_dir("security-pki-bad");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--out", dir + "/a", "--robots", "0-x"}, "--robots '0-x'"},
      {{"--out", dir + "/a", "--robots", "5-2"}, "--robots '5-2'"},
      {{"--out", dir + "/a"}, "--robots"},
      {{"--robots", "0-3"}, "--out"},
      {{"--out", dir + "/a", "--robots", "1", "--prefix", "a//b"}, "--prefix 'a//b'"},
      {{"--out", dir + "/a", "--robots", "1", "--domains", "0-231"}, "--domains '0-231'"},
      {{"--out", dir + "/a", "--robots", "1", "--days", "0"}, "--days '0'"},
      {{"--out", "/proc/retreat-pki", "--robots", "1"}, "--out '/proc/retreat-pki'"},
      {{"--robots", "1", "--frobnicate"}, "'--frobnicate'"},
  };
  for (const auto& [args, named] : cases) {
    std::vector<std::string> argv = {"/bin/bash", pki_script};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto [code, output] = testing::run_to_exit(argv, dir + "/out.log");
    EXPECT_EQ(code, 2) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
    EXPECT_EQ(output.rfind("make-swarm-pki.sh: ", 0), 0u) << output;
    EXPECT_NE(output.find(named), std::string::npos) << output;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/a"));  // nothing made on bad input
}

// ---- secure swarms ---------------------------------------------------------------------------

struct VendorCase {
  const char* vendor;
  int domain;
};

// Test names from the values, not from the bytes of a pointer (which differ between builds).
void PrintTo(const VendorCase& c, std::ostream* os) { *os << c.vendor << " on domain " << c.domain; }

class SecureSwarm : public ::testing::TestWithParam<VendorCase> {};

TEST_P(SecureSwarm, CompletesWithThePlainRunsTrajectoryHash) {
  const auto [vendor, domain] = GetParam();
  if (!built(vendor)) GTEST_SKIP() << vendor << " not built";
  const auto dir = fresh_dir(std::string("security-swarm-") + vendor);
  const auto pki = shared_pki();
  const auto plain = run_swarm(dir + "/plain", run_args(vendor, domain));
  const auto safe = run_swarm(dir + "/secure", secure(run_args(vendor, domain), pki));
  ASSERT_FALSE(plain.empty());
  ASSERT_FALSE(safe.empty());
  EXPECT_EQ(safe["agents"]["matched"], 12);
  EXPECT_EQ(safe["agents"]["lost"], 0);
  // A decision is dropped only as an agent's second answer to a frame the arena re-sent.
  EXPECT_LE(safe["decisions_dropped"].get<std::uint64_t>(), safe["frames_resent"].get<std::uint64_t>());
  EXPECT_GT(plain["agents"]["retreated"].get<int>(), 0);  // the hash depends on the agents' decisions
  EXPECT_EQ(safe["trajectory_sha256"], plain["trajectory_sha256"]);
  // Event-driven lockstep: the agents' plans pass the permissions too (robot_<i>/plan). Recorded
  // (retreat-record with the PKI's `recorder` identity, which may read every topic): the
  // recording holds every robot's frames and answers, nothing lost or undecodable.
  auto planned_args = secure(run_args(vendor, domain), pki);
  const auto recording = dir + "/secure-plans.mcap";
  planned_args.insert(planned_args.end(), {"--set", "run.plans=true", "--record", recording});
  const auto planned = run_swarm(dir + "/secure-plans", planned_args);
  ASSERT_FALSE(planned.empty());
  EXPECT_EQ(planned["agents"]["lost"], 0);
  EXPECT_GT(planned["decisions_planned"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(planned["trajectory_sha256"], plain["trajectory_sha256"]);
  EXPECT_EQ(planned["launch"]["recording"]["recorder"], "exited with code 0") << planned.dump();
  const auto recorded = replay::load_recording(recording);
  EXPECT_EQ(recorded.recorder_dropped, 0);
  EXPECT_EQ(recorded.undecodable + recorded.invalid, 0u);
  EXPECT_FALSE(recorded.telemetry.empty());
  EXPECT_FALSE(recorded.statuses.empty());
  ASSERT_EQ(recorded.robots.size(), 12u);
  // Every frame answered but a departed one, matched by the frame's time (a plan carries the
  // time of the frame it answers). Counted by time, not by message: a frame re-sent before the
  // agent's reader matched reaches the agent once, and is answered once.
  for (const auto& [id, robot] : recorded.robots) {
    EXPECT_FALSE(robot.frames.empty()) << "robot " << id;
    std::set<double> answered;
    for (const auto& a : robot.answers) answered.insert(a.sample.time);
    for (const auto& f : robot.frames) {
      if (f.sample.phase == wire::Phase::departed) continue;
      EXPECT_EQ(answered.count(f.sample.time), 1u) << "robot " << id << ": the frame of tick " << f.sample.tick
                                                  << " has no recorded answer";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Vendor, SecureSwarm,
                         ::testing::Values(VendorCase{"fastdds", testing::domains::security.at(0)}, VendorCase{"cyclonedds", testing::domains::security.at(1)}),
                         [](const auto& test) { return std::string(test.param.vendor); });

/// A participant that tries to take part in the swarm: it reads robot 0's proximity frames and
/// answers each with a retreat, and also writes retreat decisions for robot 0 blindly, for
/// every tick of the run in turn.
struct Intruder {
  Intruder(const std::string& vendor, int domain, transport::SecurityOptions security = {})
      : t(transport::make_transport(vendor, {domain, "intruder", "retreat:agent:robot=0", "", security})),
        frames(t->create_reader<wire::ProximityFrame>({wire::proximity_topic("retreat", 0),
                                                        transport::QosIntent::control()})),
        decisions(t->create_writer<wire::Decision>({wire::decision_topic("retreat", 0),
                                                     transport::QosIntent::control()})) {}
  void spin_once() {
    t->wait(2ms);
    for (const auto& f : frames.take()) {
      ++frames_received;
      decisions.write({0, f.tick, f.time, true});
    }
    for (int i = 0; i < 4; ++i, blind_tick = (blind_tick + 1) % 4000) {
      decisions.write({0, blind_tick, 0.03 * static_cast<double>(blind_tick), true});
    }
    matched = std::max(matched, frames.matched_count() + decisions.matched_count());
  }
  std::unique_ptr<transport::Transport> t;
  transport::Reader<wire::ProximityFrame> frames;
  transport::Writer<wire::Decision> decisions;
  std::int64_t blind_tick = 0;
  std::uint64_t frames_received = 0;
  std::size_t matched = 0;
};

/// Runs a swarm with the intruder spinning beside it until the launcher ends.
json run_with_intruder(const std::string& dir, const std::vector<std::string>& args, Intruder& intruder) {
  std::filesystem::create_directories(dir);
  auto l = start_launch(dir, args);
  const auto deadline = std::chrono::steady_clock::now() + testing::hang_ceiling;
  while (l.process.running() && std::chrono::steady_clock::now() < deadline) intruder.spin_once();
  const auto code = l.process.wait_for(1s);  // it has ended, or the ceiling was reached (a hang)
  EXPECT_EQ(code, std::optional<int>(0)) << log_of(dir);
  if (!code) l.process.stop();
  return read_json(l.out + "/summary.json");
}

class SecureSwarmIntruder : public ::testing::TestWithParam<VendorCase> {};

TEST_P(SecureSwarmIntruder, WithoutAnIdentitySeesNoRobotAndCannotInjectADecision) {
  const auto [vendor, domain] = GetParam();
  if (!built(vendor)) GTEST_SKIP() << vendor << " not built";
  const auto dir = fresh_dir(std::string("security-intruder-") + vendor);
  const auto pki = shared_pki();
  // The reference trajectory: the same run in one process (the same hash as over any vendor).
  const auto plain = run_swarm(dir + "/plain", {robotarium, "--in-process", "--seed", "1", "--set", "run.duration=120"});
  ASSERT_FALSE(plain.empty());

  // Control: without security the same intruder gets in (frames read, decisions taken or
  // dropped by the arena), so the check below would see an injection.
  {
    Intruder intruder(vendor, domain);
    const auto open = run_with_intruder(dir + "/open", run_args(vendor, domain), intruder);
    ASSERT_FALSE(open.empty());
    EXPECT_GT(intruder.frames_received, 0u);
    EXPECT_TRUE(open["trajectory_sha256"] != plain["trajectory_sha256"] ||
                open["decisions_dropped"].get<std::uint64_t>() > 0)
        << "the unsecured swarm did not notice the intruder";
  }

  Intruder intruder(vendor, domain);
  const auto safe = run_with_intruder(dir + "/secure", secure(run_args(vendor, domain), pki), intruder);
  ASSERT_FALSE(safe.empty());
  // Participant announcements (SPDP) stay readable by design of DDS Security; every endpoint
  // (SEDP) and every sample is protected: the intruder matches nothing and reads nothing.
  EXPECT_EQ(intruder.matched, 0u) << "an unauthenticated participant matched a robot's topic";
  EXPECT_EQ(intruder.frames_received, 0u);
  EXPECT_EQ(safe["agents"]["matched"], 12);
  EXPECT_EQ(safe["agents"]["lost"], 0);
  // Every decision the arena dropped is an agent's second answer to a re-sent frame (at most one
  // per re-sent frame); the intruder's thousands of writes (the control above) never arrived.
  EXPECT_LE(safe["decisions_dropped"].get<std::uint64_t>(), safe["frames_resent"].get<std::uint64_t>());
  EXPECT_EQ(safe["trajectory_sha256"], plain["trajectory_sha256"]);
}

INSTANTIATE_TEST_SUITE_P(Vendor, SecureSwarmIntruder,
                         ::testing::Values(VendorCase{"fastdds", testing::domains::security.at(2)}, VendorCase{"cyclonedds", testing::domains::security.at(3)}),
                         [](const auto& test) { return std::string(test.param.vendor); });

// ---- permissions, one participant in this process -------------------------------------------

class SecurePermissions : public ::testing::TestWithParam<VendorCase> {
 protected:
  std::unique_ptr<transport::Transport> participant(const std::string& identity) {
    const auto pki = shared_pki();
    return transport::make_transport(GetParam().vendor,
                                     {GetParam().domain, "permissions-test", "", "",
                                      transport::swarm_identity(pki, identity)});
  }
};

/// The error of `create`, which must be one line naming `topic`.
template <class F>
void expect_refused(F&& create, const std::string& topic) {
  try {
    create();
    ADD_FAILURE() << "created an endpoint on " << topic << " without permission";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find(topic), std::string::npos) << what;
  }
}

TEST_P(SecurePermissions, AnAgentHoldingRobot3sIdentityCannotReadRobot4sProximity) {
  if (!built(GetParam().vendor)) GTEST_SKIP() << GetParam().vendor << " not built";
  auto t = participant("robot_3");
  // Its own topics are granted: the identity itself is good.
  auto own = t->create_reader<wire::ProximityFrame>({wire::proximity_topic("retreat", 3), transport::QosIntent::control()});
  auto decision = t->create_writer<wire::Decision>({wire::decision_topic("retreat", 3), transport::QosIntent::control()});
  const auto other = wire::proximity_topic("retreat", 4);
  expect_refused([&] { t->create_reader<wire::ProximityFrame>({other, transport::QosIntent::control()}); }, other);
  const auto other_decision = wire::decision_topic("retreat", 4);
  expect_refused([&] { t->create_writer<wire::Decision>({other_decision, transport::QosIntent::control()}); },
                 other_decision);
}

TEST_P(SecurePermissions, TheBridgeIdentityCannotWriteADecision) {
  if (!built(GetParam().vendor)) GTEST_SKIP() << GetParam().vendor << " not built";
  auto t = participant("bridge");
  auto telemetry = t->create_reader<wire::ArenaTelemetry>(
      {wire::arena_telemetry_topic("retreat"), transport::QosIntent::state()});
  const auto topic = wire::decision_topic("retreat", 0);
  expect_refused([&] { t->create_writer<wire::Decision>({topic, transport::QosIntent::control()}); }, topic);
  const auto telemetry_topic = wire::arena_telemetry_topic("retreat");
  expect_refused([&] { t->create_writer<wire::ArenaTelemetry>({telemetry_topic, transport::QosIntent::state()}); },
                 telemetry_topic);
}

INSTANTIATE_TEST_SUITE_P(Vendor, SecurePermissions,
                         ::testing::Values(VendorCase{"fastdds", testing::domains::security.at(4)}, VendorCase{"cyclonedds", testing::domains::security.at(5)}),
                         [](const auto& test) { return std::string(test.param.vendor); });

// ---- the launcher ----------------------------------------------------------------------------

TEST(SecureLaunch, RefusesMixedVendorsWithOneLine) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const auto dir = fresh_dir("security-mixed");
  const auto code = run_launch(dir, secure({robotarium, "--dds", "mixed", "--domain", std::to_string(testing::domains::security.at(6))}, shared_pki()));
  EXPECT_EQ(code, 2);
  const auto log = log_of(dir);
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
  EXPECT_NE(log.find("--dds mixed"), std::string::npos) << log;
}

// ---- a real robot's link -----------------------------------------------------------------------

TEST(SecureRobotLink, TheExampleRobotJoinsASecureSwarmWithTheArenaIdentityAndIsAnswered) {
  // The robot link takes the swarm PKI's `arena` identity (docs/robot-guide.md): its permissions
  // grant writing robot 3's frames and reading its decisions. Lockstep, so that every frame is
  // answered by the agent holding robot 3's identity. Domain 72, one vendor after the other.
  const auto pki = shared_pki();
  for (const std::string vendor : {"fastdds", "cyclonedds"}) {
    if (!built(vendor)) continue;
    SCOPED_TRACE(vendor);
    const auto dir = fresh_dir("security-robot-link-" + vendor);
    const auto scenario = dir + "/scenario.yaml";
    std::ofstream(scenario) << "name: secure-robot-link\nseed: 11\n"
                            << "agent: {L: 3, dt: 0.1, K_p: 0.5, lambda_in: 0}\n"
                            << "run: {mode: lockstep, startup_timeout: 60}\n"
                            << "dds: {vendor: " << vendor << ", domain: " << testing::domains::security.at(7) << ", security: on, security_dir: " << pki << "}\n";
    testing::ChildProcess agent({RETREAT_AGENT_BIN, "--robot-id", "3", "--scenario", scenario}, dir + "/agent.log");
    // Without an identity the same robot never reaches its agent: security is on.
    const auto [plain, refused] = testing::run_to_exit(
        {RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "3", "--dds", vendor, "--domain", std::to_string(testing::domains::security.at(7)), "--lockstep",
         "--agent-timeout", "3"},
        dir + "/plain.log");
    EXPECT_EQ(plain, 1) << refused;
    EXPECT_NE(refused.find("no agent matched"), std::string::npos) << refused;
    const auto [code, output] = testing::run_to_exit(
        {RETREAT_ROBOT_EXAMPLE_BIN, "--robot-id", "3", "--scenario", scenario, "--onset-rate", "6", "--seed", "2"},
        dir + "/robot.log");
    EXPECT_EQ(code, 0) << output << testing::read_file(dir + "/agent.log");
    EXPECT_NE(output.find("departed"), std::string::npos) << output;
    const auto agent_code = agent.wait_for(testing::hang_ceiling);
    ASSERT_TRUE(agent_code.has_value()) << "the agent did not exit after its robot departed";
    EXPECT_EQ(*agent_code, 0);
  }
}

}  // namespace
}  // namespace retreat::launch_test
