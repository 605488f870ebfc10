// retreat-launch refuses bad input before starting anything: exit code 2, and no run directory
// (the launcher creates it only after every check passed, before the first child starts).

#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "retreat/testing/domains.hpp"
#include "launch_support.hpp"

namespace retreat::launch_test {
namespace {

// Domain ids of this file: 59 (held by the test itself); 64 named in refused launches (never
// joined: the launcher refuses before it takes a domain).
constexpr int domain_held = testing::domains::launch.at(9);

/// Refused with exit code 2 and nothing started; with @p line, in that one line.
void expect_refused(const std::string& name, const std::vector<std::string>& args, const std::string& line = "") {
  const auto dir = fresh_dir("input-" + name);
  EXPECT_EQ(run_launch(dir, args), 2) << name << ": " << log_of(dir);
  if (!line.empty()) EXPECT_EQ(log_of(dir), "retreat-launch: " + line + "\n") << name;
  // Refused before anything started: the run directory is made just before the first child.
  EXPECT_FALSE(std::filesystem::exists(dir + "/run")) << name << ": something was started";
}

TEST(LaunchInput, BadInputIsRefusedWithExitCodeTwoAndNothingStarted) {
  expect_refused("missing-scenario", {scenarios + "/no-such-scenario.yaml", "--domain", "64"});
  expect_refused("seeds-backwards", {robotarium, "--seeds", "5:2", "--domain", "64"});
  expect_refused("seeds-not-numbers", {robotarium, "--seeds", "a:b", "--domain", "64"});
  expect_refused("unknown-dds", {robotarium, "--dds", "zenoh", "--domain", "64"});
  expect_refused("unknown-key", {robotarium, "--set", "arena.colour=blue", "--domain", "64"});
  expect_refused("unknown-section", {robotarium, "--set", "physics.dt=1", "--domain", "64"});
  expect_refused("bad-value", {robotarium, "--set", "run.duration=-1", "--domain", "64"});
  expect_refused("domain-out-of-range", {robotarium, "--domain", "300"});
  expect_refused("seed-and-seeds", {robotarium, "--seed", "1", "--seeds", "1:2", "--domain", "64"});
  expect_refused("dds-in-process", {robotarium, "--in-process", "--dds", "fastdds"});
  expect_refused("realtime-in-process", {robotarium, "--in-process", "--set", "run.mode=realtime"});
  expect_refused("unknown-option", {robotarium, "--frobnicate"});
  expect_refused("missing-programs", {robotarium, "--bin-dir", "/nonexistent", "--domain", "64"});
  expect_refused("jobs-zero", {robotarium, "--in-process", "--seeds", "1:2", "--jobs", "0"});
  expect_refused("jobs-too-many", {robotarium, "--in-process", "--seeds", "1:2", "--jobs", "257"});
  expect_refused("jobs-not-a-number", {robotarium, "--in-process", "--jobs", "two"});
  // Whole numbers are decimal and in range: CLI11 alone ran "--seed -1" as seed
  // 18446744073709551615, a seed past the range as that one too, and "--domain 0x10" on domain 16.
  expect_refused("seed-negative", {robotarium, "--in-process", "--seed", "-1"},
                 "--seed '-1': must be a whole number in 0..18446744073709551615");
  expect_refused("seed-past-range", {robotarium, "--in-process", "--seed", "18446744073709551616"},
                 "--seed '18446744073709551616': must be a whole number in 0..18446744073709551615");
  expect_refused("domain-hex", {robotarium, "--domain", "0x10"}, "--domain '0x10': must be a whole number in 0..232");
  expect_refused("jobs-negative", {robotarium, "--in-process", "--seeds", "1:2", "--jobs", "-1"},
                 "--jobs '-1': must be a whole number in 1..256");
  expect_refused("jobs-in-processes", {robotarium, "--seeds", "1:2", "--jobs", "2", "--domain", "64"});
  const std::string mcap = ::testing::TempDir() + "/refused.mcap";
  expect_refused("record-in-process", {robotarium, "--in-process", "--record", mcap});
  expect_refused("recorders-in-process", {robotarium, "--in-process", "--set", "run.recorders=1"});
  expect_refused("recorders-out-of-range", {robotarium, "--set", "run.recorders=9", "--domain", "64"});
  expect_refused("record-no-directory",
                 {robotarium, "--dds", "cyclonedds", "--record", "/nonexistent/run.mcap", "--domain", "64"});
  EXPECT_FALSE(std::filesystem::exists(mcap)) << "a refused launch wrote its recording";
}

TEST(LaunchInput, AScenarioThatWouldHangOrExhaustMemoryIsRefusedInOneLineNamingItsKey) {
  // Before these limits: an influx of 1e300 robots/(m^2 s) and 10^9 tumbles a second looped over
  // their events forever, deaf to SIGTERM; 1e9 pick-up locations per m^2 and 10^8 waiting robots
  // ended in "std::bad_alloc" (or the OOM killer); a 1e30 m arena was refused as
  // "arena.robots_inside = 8: must be <= 0".
  const std::string endless = scenarios + "/steady-influx.yaml";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--set", "agent.lambda_in=1e300"}, "agent.lambda_in = 1e+300: must be <= "},
      {{"--set", "model.lambda_p=1e9"}, "model.lambda_p = 1000000000: must be <= "},
      {{"--set", "arena.robots_waiting=100000000"}, "arena.robots_waiting = 100000000: must be <= 999992 "},
      {{"--set", "arena.semi_axis_x=1e30"}, "arena.semi_axis_x = 1e+30: must be <= 1000000 m"},
      {{"--set", "arena.tumble_rate=1e9"}, "arena.tumble_rate = 1000000000: must be <= "},
      {{"--set", "arena.physics_dt=1e-12"}, "arena.physics_dt = 1e-12: must be >= "},
  };
  for (const auto& [set, line] : cases) {
    const auto dir = fresh_dir("input-limits");
    std::vector<std::string> args = {endless, "--in-process", "--no-bridge"};
    args.insert(args.end(), set.begin(), set.end());
    EXPECT_EQ(run_launch(dir, args), 2) << set[1] << ": " << log_of(dir);
    const auto log = log_of(dir);
    EXPECT_EQ(log.rfind("retreat-launch: " + line, 0), 0u) << set[1] << ": " << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << "one line: " << log;
    EXPECT_FALSE(std::filesystem::exists(dir + "/run")) << set[1] << ": something was started";
  }
}

TEST(LaunchInput, InProcessRobotsTheHostsMemoryCannotHoldAreRefusedBeforeAnythingStarts) {
  // 64 seeds at once of 10^6 robots: about 64 · 15.3 GiB, beyond any host this suite runs on (the
  // unit tests cover a lowered default and a single run too big). Before this check such a launch
  // started and was killed by the kernel's OOM killer part-way, its runs lost.
  const auto dir = fresh_dir("input-in-process-memory");
  EXPECT_EQ(run_launch(dir, {scenarios + "/kinetic-1000.yaml", "--in-process", "--no-bridge", "--seeds", "1:64",
                             "--jobs", "64", "--set", "arena.robots_inside=1000000", "--set", "arena.width=790",
                             "--set", "arena.height=790"}),
            2)
      << log_of(dir);
  const auto log = log_of(dir);
  EXPECT_EQ(log.rfind("retreat-launch: --jobs 64: 1000000 robots (arena.robots_inside + arena.robots_waiting) with "
                      "their agents need about 15625 MiB of memory a run, 64 at once about 1000000 MiB",
                      0),
            0u)
      << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << "one line: " << log;
  EXPECT_FALSE(std::filesystem::exists(dir + "/run")) << "something was started";
}

TEST(LaunchInput, ARunDirectoryThatHoldsARecordedRunIsNotOverwritten) {
  // --out naming an earlier run's directory: the launcher used to write the new run over it.
  struct Case {
    std::string name;
    std::vector<std::string> args;
    std::string recorded;  ///< the earlier run's file, below <dir>/run
  };
  const std::vector<Case> cases = {
      {"in-process", {robotarium, "--in-process"}, "summary.json"},
      {"processes", {robotarium, "--domain", "64"}, "telemetry.csv"},
      {"one-seed-of-several", {robotarium, "--in-process", "--seeds", "1:3"}, "seed_2/telemetry.csv"},
  };
  for (const auto& c : cases) {
    const auto dir = fresh_dir("input-recorded-" + c.name);
    const auto file = dir + "/run/" + c.recorded;
    std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    std::ofstream(file) << "an earlier run\n";
    EXPECT_EQ(run_launch(dir, c.args), 2) << c.name << ": " << log_of(dir);
    EXPECT_EQ(log_of(dir), "retreat-launch: --out '" + dir + "/run': holds a recorded run (" + file +
                               "); give a new directory (a run directory is never overwritten)\n")
        << c.name;
    EXPECT_EQ(testing::read_file(file), "an earlier run\n") << c.name;
    EXPECT_FALSE(std::filesystem::exists(dir + "/run/logs")) << c.name << ": a process was started";
    EXPECT_FALSE(std::filesystem::exists(dir + "/run/seed_1")) << c.name << ": a seed was run";
  }
}

TEST(LaunchInput, ASwarmBeyondWhatItsDdsSettingsDiscoverIsRefusedWithTheLimitAndTheWayOut) {
  // kinetic-1000 without a bridge: 1,000 agents, the arena and the launcher, with the built-in settings
  // (participant indices 0..119 per domain); the unit tests cover profiles, tasks and memory.
  const auto dir = fresh_dir("input-capacity");
  EXPECT_EQ(run_launch(dir, {scenarios + "/kinetic-1000.yaml", "--domain", "64"}), 2) << log_of(dir);
  const auto log = log_of(dir);
  EXPECT_NE(log.find("1002 DDS participants (1000 agents, the arena and the launcher)"), std::string::npos) << log;
  EXPECT_NE(log.find("discover at most 120"), std::string::npos) << log;
  EXPECT_NE(log.find("star profiles"), std::string::npos) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << "one line: " << log;
  EXPECT_FALSE(std::filesystem::exists(dir + "/run")) << "something was started";
}

TEST(LaunchInput, ADomainInUseByAnotherLaunchIsRefused) {
  // Hold the domain's lock as another launcher would.
  const auto path = "/tmp/retreat-domain-" + std::to_string(domain_held) + ".lock";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0) << "another process holds " << path;
  expect_refused("domain-in-use", {robotarium, "--domain", std::to_string(domain_held)});
  ::close(fd);
}

}  // namespace
}  // namespace retreat::launch_test
