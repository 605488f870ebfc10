// Faults beyond a lost agent (issue 8): a bridge killed mid-run, repeatedly, is restarted by the
// launcher and the run directory loses nothing; a real-time arena killed mid-run is resumed from
// the run directory and the same agent processes go on with it. Assertions are on the run
// directory's files. A lockstep arena killed and resumed (by hand, and by the launcher) gives the trajectory of the
// uninterrupted run: the replay rebuilds the world exactly. A /dev/shm full of stale Fast DDS
// segments is cleaned by the launcher and the run completes; one full of something else is
// refused in one line. The launcher resumes a lockstep arena killed mid-run by itself, and the
// run has the uninterrupted trajectory, over each vendor. Domain ids of this file: 73..79.

#include <gtest/gtest.h>
#include <unistd.h>

#include <deque>
#include <fstream>
#include <sstream>

#include "retreat/testing/domains.hpp"
#include "launch_support.hpp"

namespace retreat::launch_test {
namespace {

constexpr int domain_kill_bridge = testing::domains::faults.at(0);
constexpr int domain_kill_realtime_arena = testing::domains::faults.at(1);
constexpr int domain_resume_lockstep_arena = testing::domains::faults.at(2);
constexpr int domain_launcher_resumes_lockstep_fastdds = testing::domains::faults.at(3);
constexpr int domain_launcher_resumes_lockstep_cyclonedds = testing::domains::faults.at(6);
constexpr int domain_shm_stale = testing::domains::faults.at(4);
constexpr int domain_shm_full = testing::domains::faults.at(5);

/// The file's complete lines (a half-written last line is left out).
std::vector<std::string> lines_of(const std::string& path) {
  std::vector<std::string> out;
  std::string text = testing::read_file(path);
  const auto end = text.rfind('\n');
  text = end == std::string::npos ? "" : text.substr(0, end + 1);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// The first CSV column of a row as an integer.
std::int64_t first_field(const std::string& row) {
  return std::stoll(row.substr(0, row.find(',')));
}
/// The first CSV column of a row as a number.
double first_number(const std::string& row) { return std::stod(row.substr(0, row.find(','))); }

TEST(Faults, ABridgeKilledTwiceMidRunIsRestartedAndTheRunDirectoryLosesNothing) {
  if (::access(bridge_program.c_str(), X_OK) != 0) GTEST_SKIP() << "retreat-bridge is not built";
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  const auto dir = fresh_dir("faults-bridge");
  // 800 simulated seconds: 26,667 per-tick lockstep ticks, ~20 s of wall time over Fast DDS,
  // enough for two kills and restarts (a bridge starts and matches in about a second; with the
  // shipped scenario's plans the run would end within a second).
  auto l = start_launch(dir,
                        {robotarium, "--dds", vendor, "--domain", std::to_string(domain_kill_bridge), "--set",
                         "run.duration=800", "--set", "bridge.http=127.0.0.1:0", "--set", "run.plans=false"},
                        /*bridge=*/true);
  const std::string status_csv = l.out + "/agent_status.csv";
  std::vector<std::vector<std::string>> before_kill;  // agent_status.csv as each kill found it
  pid_t previous = -1;
  for (int kill = 0; kill < 2; ++kill) {
    json processes;
    // The current bridge: a new PID in processes.json that has recorded statuses of its own.
    const std::size_t rows_so_far = before_kill.empty() ? 1 : before_kill.back().size();
    ASSERT_TRUE(testing::eventually(
        [&] {
          processes = read_json(l.out + "/processes.json");
          return !processes.empty() && !processes["bridge"].is_null() &&
                 processes["bridge"]["pid"].get<pid_t>() != previous &&
                 lines_of(status_csv).size() > rows_so_far + 12;
        },
        retreat::testing::hang_ceiling))
        << "no new bridge recording; " << log_of(dir);
    previous = processes["bridge"]["pid"].get<pid_t>();
    before_kill.push_back(lines_of(status_csv));
    ASSERT_EQ(::kill(previous, SIGKILL), 0);
  }
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  ASSERT_EQ(*code, 0) << log_of(dir);

  const auto summary = read_json(l.out + "/summary.json");
  ASSERT_FALSE(summary.empty()) << log_of(dir);
  EXPECT_EQ(summary["ticks"], 26667);
  EXPECT_EQ(summary["launch"]["bridge_restarts"], 2);
  EXPECT_TRUE(summary.contains("trajectory_sha256"));

  // telemetry.csv (the arena's): one row per tick after each step, ticks 1, 2, ... contiguous.
  const auto telemetry = lines_of(l.out + "/telemetry.csv");
  ASSERT_EQ(telemetry.size(), 1u + 26667u);
  for (std::size_t i = 1; i < telemetry.size(); ++i) {
    ASSERT_EQ(first_field(telemetry[i]), static_cast<std::int64_t>(i)) << "row " << i;
  }

  // agent_status.csv: every row on disk before each kill is still there, in place, and the
  // restarted bridges recorded statuses after the last kill.
  const auto statuses = lines_of(status_csv);
  for (const auto& prefix : before_kill) {
    ASSERT_GT(statuses.size(), prefix.size());
    for (std::size_t i = 0; i < prefix.size(); ++i)
      ASSERT_EQ(statuses[i], prefix[i]) << "row " << i;
  }
  const double last_time_before = first_number(before_kill.back().back());
  EXPECT_GT(first_number(statuses.back()), last_time_before);
  EXPECT_GT(statuses.size(), before_kill.back().size() + 12);

  // The last bridge wrote the report at the end, from the complete run directory.
  EXPECT_GT(std::filesystem::file_size(l.out + "/report.html"), 1000u);
  EXPECT_TRUE(std::filesystem::exists(l.out + "/logs/bridge.restart_2.log"));
}

std::vector<pid_t> agent_pids(const json& processes) {
  std::vector<pid_t> out;
  for (const auto& a : processes["agents"]) out.push_back(a["pid"].get<pid_t>());
  return out;
}

TEST(Faults, AKilledRealTimeArenaIsResumedAndTheSameAgentsGoOn) {
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  const auto dir = fresh_dir("faults-arena");
  // Real time at twice the wall clock: 40 simulated seconds, 1,334 ticks, ~20 s of wall time.
  auto l = start_launch(
      dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain_kill_realtime_arena),
            "--set", "run.mode=realtime", "--set", "run.speed=2", "--set", "run.duration=40"});
  const std::string telemetry_csv = l.out + "/telemetry.csv";
  json before;
  ASSERT_TRUE(testing::eventually(
      [&] {
        before = read_json(l.out + "/processes.json");
        return !before.empty() && lines_of(telemetry_csv).size() > 300;  // past tick 300 (9 s)
      },
      retreat::testing::hang_ceiling))
      << log_of(dir);
  const auto agents = agent_pids(before);
  ASSERT_EQ(agents.size(), 12u);
  const pid_t first_arena = before["arena"]["pid"].get<pid_t>();
  const std::int64_t last_row_seen = first_field(lines_of(telemetry_csv).back());
  ASSERT_EQ(::kill(first_arena, SIGKILL), 0);

  json after;
  ASSERT_TRUE(testing::eventually(
      [&] {
        after = read_json(l.out + "/processes.json");
        return !after.empty() && after["arena"]["pid"].get<pid_t>() != first_arena;
      },
      retreat::testing::hang_ceiling))
      << "the launcher did not restart the arena; " << log_of(dir);
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  ASSERT_EQ(*code, 0) << log_of(dir);

  // The same agent processes served both arenas: no agent was restarted.
  EXPECT_EQ(agent_pids(read_json(l.out + "/processes.json")), agents);
  const auto summary = read_json(l.out + "/summary.json");
  ASSERT_FALSE(summary.empty()) << log_of(dir);
  EXPECT_EQ(summary["launch"]["arena_restarts"], 1);
  EXPECT_EQ(summary["ticks"], 1334);
  EXPECT_EQ(summary["agents"]["lost"], 0);
  ASSERT_TRUE(summary.contains("resumed_at_tick"));
  const auto resumed_at = summary["resumed_at_tick"].get<std::int64_t>();
  EXPECT_GE(resumed_at, last_row_seen);  // every tick the dead arena stepped was kept
  EXPECT_LT(resumed_at, 1334);
  // Written by the resumed arena: decisions reached it, about 12 per tick after the restart
  // (at least half of them: real time applies whatever has arrived, late ones count too).
  EXPECT_GT(summary["decisions_received"].get<std::int64_t>(), (1334 - resumed_at) * 12 / 2);

  // telemetry.csv: one row per tick, 1..1334, no tick missing or repeated across the restart.
  const auto telemetry = lines_of(telemetry_csv);
  ASSERT_EQ(telemetry.size(), 1u + 1334u);
  for (std::size_t i = 1; i < telemetry.size(); ++i) {
    ASSERT_EQ(first_field(telemetry[i]), static_cast<std::int64_t>(i)) << "row " << i;
  }
  EXPECT_TRUE(std::filesystem::exists(l.out + "/agents.csv"));
  EXPECT_TRUE(std::filesystem::exists(l.out + "/logs/arena.restart_1.log"));
}

// The launcher fails a lockstep run whose arena dies (launch_faults_test); by hand, with the
// agents still running, `retreat-arena --resume` continues it, and lockstep makes the outcome
// checkable: the trajectory hash of the uninterrupted run with the same seed.
TEST(Faults, ALockstepArenaResumedByHandGivesTheUninterruptedTrajectory) {
  const std::string vendor = built("fastdds") ? "fastdds" : "cyclonedds";
  const auto dir = fresh_dir("faults-resume-lockstep");
  // 200 simulated seconds (6,667 ticks); the first retreats come after L = 90 s (~tick 3,000).
  // (The launcher's test below runs past what a keep-all decision writer held for the dead arena.)
  std::filesystem::create_directories(dir + "/reference");
  ASSERT_EQ(
      run_launch(dir + "/reference", {robotarium, "--in-process", "--set", "run.duration=200"}), 0)
      << log_of(dir + "/reference");
  const auto reference = read_json(dir + "/reference/run/summary.json");
  ASSERT_FALSE(reference.empty());

  const std::string out = dir + "/run";
  const std::vector<std::string> common = {
      "--scenario", robotarium,        "--dds",
      vendor,       "--domain",        std::to_string(domain_resume_lockstep_arena),
      "--set",      "run.duration=200", "--set", "run.plans=false"};  // per tick: killed mid-run
  auto arena_args = std::vector<std::string>{RETREAT_ARENA_BIN, "--out", out};
  arena_args.insert(arena_args.end(), common.begin(), common.end());
  std::deque<testing::ChildProcess> agents;
  for (int robot = 0; robot < 12; ++robot) {
    auto args = std::vector<std::string>{RETREAT_AGENT_BIN, "--robot-id", std::to_string(robot)};
    args.insert(args.end(), common.begin(), common.end());
    agents.emplace_back(args, dir + "/agent_" + std::to_string(robot) + ".log");
  }
  {
    testing::ChildProcess arena(arena_args, dir + "/arena.log");
    // Killed once some retreats are journalled, so that the replay has decisions to apply.
    ASSERT_TRUE(
        testing::eventually([&] { return lines_of(out + "/retreats.csv").size() > 3; }, retreat::testing::hang_ceiling))
        << testing::read_file(dir + "/arena.log");
    ASSERT_EQ(::kill(arena.pid(), SIGKILL), 0);
    arena.wait_for(retreat::testing::hang_ceiling);
  }
  const auto killed_at = first_field(lines_of(out + "/telemetry.csv").back());
  arena_args.push_back("--resume");
  testing::ChildProcess resumed(arena_args, dir + "/arena-resumed.log");
  const auto code = resumed.wait_for(retreat::testing::hang_ceiling);
  for (auto& a : agents) a.stop();
  ASSERT_TRUE(code.has_value()) << testing::read_file(dir + "/arena-resumed.log");
  ASSERT_EQ(*code, 0) << testing::read_file(dir + "/arena-resumed.log");

  const auto summary = read_json(out + "/summary.json");
  ASSERT_FALSE(summary.empty());
  EXPECT_EQ(summary["resumed_at_tick"], killed_at);
  EXPECT_EQ(summary["ticks"], 6667);
  EXPECT_EQ(summary["agents"]["lost"], 0);
  EXPECT_EQ(summary["trajectory_sha256"], reference["trajectory_sha256"]);
  EXPECT_EQ(summary["deliveries"], reference["deliveries"]);
  EXPECT_EQ(summary["agents"]["retreated"], reference["agents"]["retreated"]);
  // The hash chain and the transitions (retreat-diff's input) are the uninterrupted run's.
  EXPECT_EQ(testing::read_file(out + "/chain.bin"), testing::read_file(dir + "/reference/run/chain.bin"));
  EXPECT_EQ(testing::read_file(out + "/transitions.csv"), testing::read_file(dir + "/reference/run/transitions.csv"));
  const auto telemetry = lines_of(out + "/telemetry.csv");
  ASSERT_EQ(telemetry.size(), 1u + 6667u);
  for (std::size_t i = 1; i < telemetry.size(); ++i) {
    ASSERT_EQ(first_field(telemetry[i]), static_cast<std::int64_t>(i)) << "row " << i;
  }
}

struct Vendor {
  const char* name;
  int domain;
  bool plans = false;  ///< run.plans (with a 2-tick horizon: frames every other tick or so)
  friend void PrintTo(const Vendor& v, std::ostream* os) { *os << v.name << (v.plans ? " with plans" : ""); }
};

class LauncherResumesLockstep : public ::testing::TestWithParam<Vendor> {};

/// The telemetry row ticks of `<out>/telemetry.csv` are 1..ticks, each once.
void expect_every_tick_once(const std::string& out, std::int64_t ticks) {
  const auto telemetry = lines_of(out + "/telemetry.csv");
  ASSERT_EQ(telemetry.size(), 1u + static_cast<std::size_t>(ticks));
  for (std::size_t i = 1; i < telemetry.size(); ++i) {
    ASSERT_EQ(first_field(telemetry[i]), static_cast<std::int64_t>(i)) << "row " << i;
  }
}

// The launcher resumes a lockstep arena killed by a signal as it does a real-time one, with the
// same agent processes, and lockstep makes the outcome checkable: the trajectory of the
// uninterrupted run of the same scenario and seed, computed here in process (launch_runs_test
// proves in-process and process runs equal).
TEST_P(LauncherResumesLockstep, AnArenaKilledMidRunAndTheRunHasTheUninterruptedTrajectory) {
  const std::string vendor = GetParam().name;
  if (!built(vendor)) GTEST_SKIP() << vendor << " is not built";
  const auto dir = fresh_dir("faults-launcher-resumes-lockstep-" + vendor + (GetParam().plans ? "-plans" : ""));
  // 400 simulated seconds (13,334 ticks); the first retreats come after L = 90 s (~tick 3,000).
  // Killed once some are journalled, about 10,000 ticks remain: more than an agent's keep-all
  // decision writer could hold for the dead arena (Fast DDS 4,096 samples) before its lease
  // expired (20 s) when the machine runs them that fast; a bounded writer never blocks on it.
  // Per tick (the plans case adds run.plans=true after): the run lasts long enough to kill in.
  const std::vector<std::string> run = {robotarium, "--set", "run.duration=400", "--set", "seed=5", "--set",
                                        "run.plans=false"};
  constexpr std::int64_t ticks = 13334;
  auto reference_args = run;
  reference_args.push_back("--in-process");
  std::filesystem::create_directories(dir + "/reference");
  ASSERT_EQ(run_launch(dir + "/reference", reference_args), 0) << log_of(dir + "/reference");
  const auto reference = read_json(dir + "/reference/run/summary.json");
  ASSERT_FALSE(reference.empty());

  auto args = run;
  for (const auto& a : {std::string("--dds"), vendor, std::string("--domain"), std::to_string(GetParam().domain)}) {
    args.push_back(a);
  }
  if (GetParam().plans) {
    // Event-driven lockstep: the new arena takes over with no plan and asks every robot; each
    // agent acts first on the ticks the dead arena covered with its plan (docs/protocol.md §6).
    args.insert(args.end(), {"--set", "run.plans=true", "--set", "run.plan_horizon=2"});
  }
  auto l = start_launch(dir, args);
  json before;
  ASSERT_TRUE(testing::eventually(
      [&] {
        before = read_json(l.out + "/processes.json");
        return !before.empty() && lines_of(l.out + "/retreats.csv").size() > 3;
      },
      retreat::testing::hang_ceiling))
      << log_of(dir);
  const auto agents = agent_pids(before);
  const pid_t first_arena = before["arena"]["pid"].get<pid_t>();
  ASSERT_EQ(::kill(first_arena, SIGKILL), 0);

  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  if (!code) l.process.stop();
  ASSERT_TRUE(code.has_value()) << "the launcher did not finish; " << log_of(dir);
  ASSERT_EQ(*code, 0) << log_of(dir);
  const auto after = read_json(l.out + "/processes.json");
  EXPECT_NE(after["arena"]["pid"].get<pid_t>(), first_arena);
  EXPECT_EQ(agent_pids(after), agents);  // the same agents served both arenas
  const auto summary = read_json(l.out + "/summary.json");
  ASSERT_FALSE(summary.empty()) << log_of(dir);
  EXPECT_GE(summary["launch"]["arena_restarts"].get<int>(), 1);
  EXPECT_TRUE(summary.contains("resumed_at_tick"));
  EXPECT_EQ(summary["ticks"], ticks);
  EXPECT_EQ(summary["agents"]["lost"], 0);
  EXPECT_EQ(summary["trajectory_sha256"], reference["trajectory_sha256"]);
  EXPECT_EQ(summary["deliveries"], reference["deliveries"]);
  EXPECT_EQ(summary["agents"]["retreated"], reference["agents"]["retreated"]);
  EXPECT_EQ(testing::read_file(l.out + "/chain.bin"), testing::read_file(dir + "/reference/run/chain.bin"));
  EXPECT_EQ(testing::read_file(l.out + "/transitions.csv"), testing::read_file(dir + "/reference/run/transitions.csv"));
  expect_every_tick_once(l.out, ticks);
  EXPECT_TRUE(alive(child_pids(after)).empty());
}

INSTANTIATE_TEST_SUITE_P(Vendors, LauncherResumesLockstep,
                         ::testing::Values(Vendor{"fastdds", domain_launcher_resumes_lockstep_fastdds},
                                           Vendor{"cyclonedds", domain_launcher_resumes_lockstep_cyclonedds},
                                           Vendor{"fastdds", testing::domains::launch_plans.at(4), true},
                                           Vendor{"cyclonedds", testing::domains::launch_plans.at(5), true}),
                         [](const auto& param_info) {
                           return std::string(param_info.param.name) + (param_info.param.plans ? "_plans" : "");
                         });

/// The shipped loopback profile plus Fast DDS's shared-memory transport: what a user's profile
/// with Fast DDS defaults does (retreat's own profiles never use shared memory).
std::string write_shm_profile(const std::string& dir) {
  auto xml = testing::read_file(std::string(RETREAT_DDS_PROFILES) + "/fastdds-loopback.xml");
  const auto add = [&](const std::string& after, const std::string& text) {
    const auto at = xml.find(after);
    if (at == std::string::npos) return false;
    xml.insert(at + after.size(), text);
    return true;
  };
  EXPECT_TRUE(add("<transport_descriptors>",
                  "<transport_descriptor><transport_id>shm</transport_id><type>SHM</type></"
                  "transport_descriptor>"));
  EXPECT_TRUE(add("<userTransports>", "<transport_id>shm</transport_id>"));
  const std::string path = dir + "/fastdds-shm.xml";
  std::ofstream(path) << xml;
  return path;
}

/// Runs `script` with sh in a private mount namespace (`unshare -m`), where /dev/shm is a
/// 16 MiB tmpfs of its own: the host's /dev/shm is never touched. Returns the exit code.
int run_with_private_dev_shm(const std::string& dir, const std::string& script) {
  const std::string full =
      "set -u\nmount -t tmpfs -o size=16m tmpfs /dev/shm || exit 97\n" + script;
  testing::ChildProcess p({"/usr/bin/unshare", "-m", "/bin/sh", "-c", full}, dir + "/launch.log");
  const auto code = p.wait_for(retreat::testing::hang_ceiling);
  if (!code) p.stop();
  return code.value_or(-1);
}

bool can_make_mount_namespaces() {
  return ::geteuid() == 0 && ::access("/usr/bin/unshare", X_OK) == 0 &&
         ::access("/usr/bin/flock", X_OK) == 0;
}

std::string launcher_command(const std::string& dir, const std::string& profile, int domain) {
  return launcher + " " + robotarium + " --dds fastdds --domain " + std::to_string(domain) +
         " --set dds.profile=" + profile + " --set run.duration=20 --no-bridge --out " + dir +
         "/run";
}

// Twenty-one dead Fast DDS processes' segments (segment, unlocked lock file, semaphore) fill the
// 16 MiB /dev/shm; a live one (its lock held) and another program's file share it. The 14 Fast
// DDS participants of the run (arena, 12 agents, the launcher's reader) need ~0.5 MiB each.
TEST(Faults, TheLauncherClearsStaleFastDdsSegmentsFromAFullDevShmAndTheRunCompletes) {
  if (!built("fastdds")) GTEST_SKIP() << "Fast DDS is not built";
  if (!can_make_mount_namespaces())
    GTEST_SKIP() << "needs root, unshare and flock (a private /dev/shm)";
  const auto dir = fresh_dir("faults-shm-stale");
  const auto profile = write_shm_profile(dir);
  const int code = run_with_private_dev_shm(
      dir,
      "for i in $(seq 1 21); do\n"
      "  head -c 800000 /dev/zero > /dev/shm/fastrtps_dead$i 2>/dev/null\n"
      "  : > /dev/shm/fastrtps_dead${i}_el; : > /dev/shm/sem.fastrtps_dead${i}_mutex\n"
      "done\n"
      "df -k /dev/shm > " +
          dir +
          "/df-before.txt\n"
          ": > /dev/shm/fastrtps_live_el; echo x > /dev/shm/fastrtps_live; echo x > "
          "/dev/shm/other_program\n"
          "/usr/bin/flock /dev/shm/fastrtps_live_el sleep 300 & holder=$!\n"
          "sleep 0.2\n" +
          launcher_command(dir, profile, domain_shm_stale) +
          "\ncode=$?\n"
          "ls /dev/shm > " +
          dir +
          "/shm-after.txt\n"
          "kill $holder\nexit $code\n");
  ASSERT_NE(code, 97) << "could not mount a tmpfs over /dev/shm; " << log_of(dir);
  // It really was full before the launch (the last column but one of df: 100%).
  EXPECT_NE(testing::read_file(dir + "/df-before.txt").find("100%"), std::string::npos)
      << testing::read_file(dir + "/df-before.txt");
  ASSERT_EQ(code, 0) << log_of(dir);
  const auto summary = read_json(dir + "/run/summary.json");
  ASSERT_FALSE(summary.empty()) << log_of(dir);
  EXPECT_EQ(summary["ticks"], 667);
  EXPECT_EQ(summary["agents"]["lost"], 0);
  EXPECT_EQ(lines_of(dir + "/run/telemetry.csv").size(), 1u + 667u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/run/agents.csv"));
  const auto after = testing::read_file(dir + "/shm-after.txt");
  EXPECT_EQ(after.find("fastrtps_dead"), std::string::npos) << after;
  EXPECT_NE(after.find("fastrtps_live_el"), std::string::npos) << after;  // its owner lives
  EXPECT_NE(after.find("other_program"), std::string::npos) << after;     // not Fast DDS's
}

TEST(Faults, TheLauncherRefusesAFullDevShmItCannotClearWhenTheProfileUsesSharedMemory) {
  if (!built("fastdds")) GTEST_SKIP() << "Fast DDS is not built";
  if (!can_make_mount_namespaces())
    GTEST_SKIP() << "needs root, unshare and flock (a private /dev/shm)";
  const auto dir = fresh_dir("faults-shm-full");
  const auto profile = write_shm_profile(dir);
  const int code = run_with_private_dev_shm(
      dir, "head -c 17000000 /dev/zero > /dev/shm/other_program 2>/dev/null\n" +
               launcher_command(dir, profile, domain_shm_full) + "\n");
  ASSERT_NE(code, 97) << "could not mount a tmpfs over /dev/shm; " << log_of(dir);
  EXPECT_EQ(code, 2) << log_of(dir);
  EXPECT_FALSE(std::filesystem::exists(dir + "/run/summary.json"));  // nothing was started
}

}  // namespace
}  // namespace retreat::launch_test
