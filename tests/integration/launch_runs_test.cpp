// retreat-launch runs that complete: robotarium-2019 with 12 agent processes over Fast DDS,
// Cyclone DDS and mixed gives one trajectory, the same as the in-process run with the same
// seed; a different seed gives a different one; --seeds aggregates; real time passes through.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "retreat/launch/capacity.hpp"
#include "retreat/testing/domains.hpp"
#include "launch_support.hpp"

namespace retreat::launch_test {
namespace {

// Domain ids of this file: 50..53, 58, 61, 62, 63.
constexpr int domain_fastdds = testing::domains::launch.at(0);
constexpr int domain_cyclonedds = testing::domains::launch.at(1);
constexpr int domain_mixed = testing::domains::launch.at(2);
constexpr int domain_kinetic = testing::domains::launch.at(3);
constexpr int domain_realtime = testing::domains::launch.at(8);
constexpr int domain_endless = testing::domains::launch.at(11);
constexpr int domain_bridge = testing::domains::launch.at(12);
constexpr int domain_seed = testing::domains::launch.at(13);
constexpr int domain_cyclone_star = testing::domains::launch.at(14);

std::vector<std::string> args(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

/// Checks what every completed 12-agent robotarium run reports and returns its summary.
json expect_complete_robotarium(const std::string& dir, const std::string& dds) {
  const auto j = read_json(dir + "/run/summary.json");
  EXPECT_FALSE(j.empty()) << "no summary.json; " << log_of(dir);
  if (j.empty()) return j;
  EXPECT_EQ(j["dds"], dds);
  EXPECT_EQ(j["scenario"], "robotarium-2019");
  EXPECT_EQ(j["seed"], 1);
  EXPECT_EQ(j["ticks"], short_robotarium_ticks);
  EXPECT_EQ(j["agents"]["started"], 12);
  EXPECT_EQ(j["agents"]["lost"], 0);
  EXPECT_GT(j["launch"]["wall_seconds"].get<double>(), 0.0);
  if (dds == "inmemory") {
    EXPECT_FALSE(j["launch"].contains("cpu_seconds")) << "one process: no children to account";
  } else {
    // The reaped arena and agents used some CPU: 13 processes cannot start and run in 0 s.
    const auto cpu = j["launch"].value("cpu_seconds", json::object());
    EXPECT_GT(cpu.value("user", 0.0) + cpu.value("system", 0.0), 0.0) << j["launch"].dump();
  }
  EXPECT_EQ(j["trajectory_sha256"].get<std::string>().size(), 64u);
  return j;
}

TEST(LaunchRuns, RobotariumGivesOneTrajectoryOverFastDdsCycloneDdsMixedAndInProcess) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const auto fast = fresh_dir("robotarium-fastdds");
  ASSERT_EQ(run_launch(fast, args({robotarium, "--dds", "fastdds", "--domain", std::to_string(domain_fastdds)},
                                  short_robotarium)), 0) << log_of(fast);
  const auto cyclone = fresh_dir("robotarium-cyclonedds");
  ASSERT_EQ(run_launch(cyclone, args({robotarium, "--dds", "cyclonedds", "--domain",
                                      std::to_string(domain_cyclonedds)}, short_robotarium)), 0)
      << log_of(cyclone);
  const auto mixed = fresh_dir("robotarium-mixed");
  ASSERT_EQ(run_launch(mixed, args({robotarium, "--dds", "mixed", "--domain", std::to_string(domain_mixed)},
                                   short_robotarium)), 0) << log_of(mixed);
  const auto in_process = fresh_dir("robotarium-in-process");
  ASSERT_EQ(run_launch(in_process, args({robotarium, "--in-process"}, short_robotarium)), 0) << log_of(in_process);

  const auto jf = expect_complete_robotarium(fast, "fastdds");
  const auto jc = expect_complete_robotarium(cyclone, "cyclonedds");
  const auto jm = expect_complete_robotarium(mixed, "mixed");
  const auto ji = expect_complete_robotarium(in_process, "inmemory");
  ASSERT_FALSE(jf.empty() || jc.empty() || jm.empty() || ji.empty());
  EXPECT_EQ(jf["trajectory_sha256"], jc["trajectory_sha256"]);
  EXPECT_EQ(jf["trajectory_sha256"], jm["trajectory_sha256"]);
  EXPECT_EQ(jf["trajectory_sha256"], ji["trajectory_sha256"]);
  // The hashes compare decisions, not only phases: robots did retreat.
  EXPECT_GT(jf["agents"]["retreated"].get<int>(), 0);

  // Mixed: agents alternate vendors, the arena takes the other vendor from agent 0.
  EXPECT_EQ(jm["launch"]["arena_vendor"], "cyclonedds");
  EXPECT_EQ(jm["launch"]["agent_vendors"]["fastdds"], 6);
  EXPECT_EQ(jm["launch"]["agent_vendors"]["cyclonedds"], 6);
  const auto processes = read_json(mixed + "/run/processes.json");
  ASSERT_EQ(processes["agents"].size(), 12u);
  for (const auto& a : processes["agents"]) {
    EXPECT_EQ(a["vendor"], a["robot"].get<int>() % 2 == 0 ? "fastdds" : "cyclonedds");
    // Each agent ran the program with only its own vendor linked (beside the launcher in this
    // build): the two programs interoperate and give the trajectory above.
    const auto program = a["program"].get<std::string>();
    EXPECT_TRUE(program.ends_with("/retreat-agent-" + a["vendor"].get<std::string>())) << program;
  }
  // Every program's output went to its own log; every child is gone.
  for (int robot = 0; robot < 12; ++robot) {
    EXPECT_TRUE(std::filesystem::exists(mixed + "/run/logs/agent_" + std::to_string(robot) + ".log"));
  }
  EXPECT_TRUE(std::filesystem::exists(mixed + "/run/logs/arena.log"));
  EXPECT_TRUE(alive(child_pids(processes)).empty());

  // Without the single-vendor programs beside it (--bin-dir with retreat-arena and retreat-agent
  // only), the launcher starts retreat-agent, and the trajectory is the same. (The Cyclone DDS
  // run above has ended: its domain is free again.)
  const auto plain = fresh_dir("robotarium-plain-agent");
  const auto bin = plain + "/bin";
  std::filesystem::create_directories(bin);
  const auto programs = std::filesystem::path(launcher).parent_path();
  for (const char* program : {"retreat-arena", "retreat-agent"}) {
    std::filesystem::create_symlink(std::filesystem::canonical(programs / program), bin + "/" + program);
  }
  ASSERT_EQ(run_launch(plain, args({robotarium, "--dds", "cyclonedds", "--domain", std::to_string(domain_cyclonedds),
                                    "--bin-dir", bin},
                                   short_robotarium)),
            0)
      << log_of(plain);
  const auto jp = expect_complete_robotarium(plain, "cyclonedds");
  EXPECT_EQ(jp["trajectory_sha256"], jc["trajectory_sha256"]);
  const auto plain_processes = read_json(plain + "/run/processes.json");
  ASSERT_EQ(plain_processes["agents"].size(), 12u);
  for (const auto& a : plain_processes["agents"]) {
    EXPECT_EQ(a["program"], bin + "/retreat-agent");
  }
}

// The same 12 robots in the kinetic world (the other world implementation; robots retreat from
// about t = 90 s on): mixed vendors against in-process.
TEST(LaunchRuns, KineticRobotariumWithRetreatsGivesOneTrajectoryMixedAndInProcess) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const std::vector<std::string> kinetic = args(short_robotarium, {"--set", "arena.encounter_model=kinetic"});
  const auto mixed = fresh_dir("kinetic-mixed");
  ASSERT_EQ(run_launch(mixed, args({robotarium, "--dds", "mixed", "--domain", std::to_string(domain_kinetic)}, kinetic)), 0)
      << log_of(mixed);
  const auto in_process = fresh_dir("kinetic-in-process");
  ASSERT_EQ(run_launch(in_process, args({robotarium, "--in-process"}, kinetic)), 0) << log_of(in_process);
  const auto jm = read_json(mixed + "/run/summary.json");
  const auto ji = read_json(in_process + "/run/summary.json");
  ASSERT_FALSE(jm.empty() || ji.empty());
  EXPECT_GT(jm["agents"]["retreated"].get<int>(), 0);
  EXPECT_EQ(jm["agents"]["lost"], 0);
  EXPECT_EQ(jm["trajectory_sha256"], ji["trajectory_sha256"]);
  EXPECT_EQ(jm["population"]["final"], ji["population"]["final"]);
  EXPECT_EQ(jm["deliveries"], ji["deliveries"]);
}

TEST(LaunchRuns, SeedsRunOneByOneOrAtOnceAlikeAndADifferentSeedGivesADifferentTrajectory) {
  // Kinetic, so that the trajectories contain decisions to tell apart (the hash covers phases
  // and decisions, not positions).
  const std::vector<std::string> kinetic = args(short_robotarium, {"--set", "arena.encounter_model=kinetic"});
  const auto dir = fresh_dir("seeds-in-process");
  ASSERT_EQ(run_launch(dir, args({robotarium, "--in-process", "--seeds", "1:3", "--jobs", "1"}, kinetic)), 0)
      << log_of(dir);
  // Three seeds on three threads at once: every seed's run and the aggregate are the same.
  const auto parallel = fresh_dir("seeds-in-process-jobs-3");
  ASSERT_EQ(run_launch(parallel, args({robotarium, "--in-process", "--seeds", "1:3", "--jobs", "3"}, kinetic)), 0)
      << log_of(parallel);
  EXPECT_NE(log_of(parallel).find("3 seeds (3 at once)"), std::string::npos) << log_of(parallel);
  for (int seed = 1; seed <= 3; ++seed) {
    const auto one = read_json(dir + "/run/seed_" + std::to_string(seed) + "/summary.json");
    const auto at_once = read_json(parallel + "/run/seed_" + std::to_string(seed) + "/summary.json");
    ASSERT_FALSE(at_once.empty()) << "seed " << seed << ": " << log_of(parallel);
    EXPECT_EQ(at_once["trajectory_sha256"], one["trajectory_sha256"]) << "seed " << seed;
    EXPECT_EQ(at_once["population"], one["population"]) << "seed " << seed;
    EXPECT_EQ(at_once["deliveries"], one["deliveries"]) << "seed " << seed;
    EXPECT_EQ(testing::read_file(parallel + "/run/seed_" + std::to_string(seed) + "/telemetry.csv"),
              testing::read_file(dir + "/run/seed_" + std::to_string(seed) + "/telemetry.csv"))
        << "seed " << seed;
  }
  const auto agg_at_once = read_json(parallel + "/run/seeds_summary.json");
  const auto agg_one = read_json(dir + "/run/seeds_summary.json");
  EXPECT_EQ(agg_at_once["population"], agg_one["population"]);
  EXPECT_EQ(agg_at_once["deliveries"], agg_one["deliveries"]);
  std::vector<std::string> hashes;
  for (int seed = 1; seed <= 3; ++seed) {
    const auto j = read_json(dir + "/run/seed_" + std::to_string(seed) + "/summary.json");
    ASSERT_FALSE(j.empty()) << "seed " << seed;
    EXPECT_EQ(j["seed"], seed);
    hashes.push_back(j["trajectory_sha256"]);
  }
  EXPECT_NE(hashes[0], hashes[1]);
  EXPECT_NE(hashes[1], hashes[2]);
  EXPECT_NE(hashes[0], hashes[2]);

  const auto agg = read_json(dir + "/run/seeds_summary.json");
  ASSERT_FALSE(agg.empty());
  EXPECT_EQ(agg["seeds"], 3);
  ASSERT_EQ(agg["runs"].size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(agg["runs"][i]["trajectory_sha256"], hashes[i]);
  for (const char* key : {"final", "mean_last_300s"}) {
    EXPECT_EQ(agg["population"][key]["n"], 3);
    EXPECT_GE(agg["population"][key]["std"].get<double>(), 0.0);
  }
  EXPECT_GT(agg["deliveries"]["mean"].get<double>(), 0.0);

  // Seed 2 alone, in processes, is seed 2 of the sweep.
  if (!built("cyclonedds")) return;
  const auto one = fresh_dir("seed-2-cyclonedds");
  ASSERT_EQ(run_launch(one, args({robotarium, "--dds", "cyclonedds", "--domain", std::to_string(domain_seed),
                                  "--seed", "2"}, kinetic)), 0) << log_of(one);
  EXPECT_EQ(read_json(one + "/run/summary.json")["trajectory_sha256"], hashes[1]);
}

// Every shipped scenario, cut to 120 simulated seconds (past the first window L = 90 s, so
// agents decide): a sweep of two seeds one after another and both at once give the same runs.
TEST(LaunchRuns, EveryShippedScenarioSweepsAlikeOneByOneAndAtOnce) {
  std::size_t checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(scenarios)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    const auto sweep = [&](const std::string& jobs) {
      const auto dir = fresh_dir("sweep-" + name + "-jobs-" + jobs);
      EXPECT_EQ(run_launch(dir, {entry.path().string(), "--in-process", "--seeds", "1:2", "--jobs", jobs, "--set",
                                 "run.duration=120"}),
                0)
          << name << ": " << log_of(dir);
      return dir + "/run";
    };
    const auto one_by_one = sweep("1");
    const auto at_once = sweep("2");
    for (const char* seed : {"seed_1", "seed_2"}) {
      const auto a = read_json(one_by_one + "/" + seed + "/summary.json");
      const auto b = read_json(at_once + "/" + seed + "/summary.json");
      ASSERT_FALSE(a.empty() || b.empty()) << name << " " << seed;
      EXPECT_EQ(a["trajectory_sha256"].get<std::string>().size(), 64u) << name;
      EXPECT_EQ(b["trajectory_sha256"], a["trajectory_sha256"]) << name << " " << seed;
      EXPECT_EQ(testing::read_file(at_once + "/" + seed + "/telemetry.csv"),
                testing::read_file(one_by_one + "/" + seed + "/telemetry.csv"))
          << name << " " << seed;
    }
    ++checked;
  }
  EXPECT_GE(checked, 5u) << "the shipped scenarios were not found in " << scenarios;
}

// A swarm that empties ends its run early; its statistics still cover run.duration, with the
// missing time as an empty swarm (issue 14: the mean of the last 300 s used to average the
// crowded start). With a tiny C, λ* is 0.03 robots/m², so every one of the 8 robots leaves at its
// first decision (L = 60 s): the run ends near 100 s, long before the last 300 s of 400.
TEST(LaunchRuns, ASwarmThatEmptiesEarlyCountsTheRestOfTheRunAsEmpty) {
  const auto dir = fresh_dir("emptied-early");
  ASSERT_EQ(run_launch(dir, {robotarium, "--in-process", "--set", "model.C=1e-6", "--set", "agent.L=60", "--set",
                             "arena.robots_waiting=0", "--set", "run.duration=400"}),
            0)
      << log_of(dir);
  const auto j = read_json(dir + "/run/summary.json");
  ASSERT_FALSE(j.empty()) << log_of(dir);
  EXPECT_EQ(j["population"]["final"], 0);
  EXPECT_EQ(j["run_duration"], 400.0);
  ASSERT_TRUE(j["population"]["emptied_at"].is_number()) << j.dump();
  const double emptied_at = j["population"]["emptied_at"].get<double>();
  EXPECT_GT(emptied_at, 60.0);  // nobody decides before L
  EXPECT_LT(emptied_at, 100.0) << "the scenario no longer empties early; the test needs another one";
  EXPECT_EQ(j["simulated_seconds"], emptied_at);
  EXPECT_EQ(j["population"]["mean_last_300s"], 0.0);  // [100, 400] s: nobody inside

  // A run that does not empty says so, and keeps its own last 300 s.
  const auto full = fresh_dir("not-emptied");
  ASSERT_EQ(run_launch(full, args({robotarium, "--in-process"}, short_robotarium)), 0) << log_of(full);
  const auto f = read_json(full + "/run/summary.json");
  ASSERT_FALSE(f.empty()) << log_of(full);
  EXPECT_TRUE(f["population"]["emptied_at"].is_null());
  EXPECT_GT(f["population"]["mean_last_300s"].get<double>(), 0.0);
}

// Sensing noise (arena.missed_onsets, arena.false_onsets) changes what the agents hear in both
// worlds, the same way on every run of the same seed.
TEST(LaunchRuns, SensingNoiseChangesTheDecisionsInBothWorldsReproducibly) {
  for (const std::string world : {"physical", "kinetic"}) {
    const auto run = [&](const std::string& name, const std::vector<std::string>& noise) {
      const auto dir = fresh_dir("noise-" + world + "-" + name);
      std::vector<std::string> argv = {robotarium, "--in-process", "--set", "run.duration=200", "--set",
                                       "arena.encounter_model=" + world};
      for (const auto& n : noise) argv.insert(argv.end(), {"--set", n});
      EXPECT_EQ(run_launch(dir, argv), 0) << log_of(dir);
      return read_json(dir + "/run/summary.json");
    };
    const auto clean = run("clean", {});
    const auto noisy = run("noisy", {"arena.missed_onsets=0.4", "arena.false_onsets=0.05"});
    const auto again = run("again", {"arena.missed_onsets=0.4", "arena.false_onsets=0.05"});
    ASSERT_FALSE(clean.empty() || noisy.empty() || again.empty()) << world;
    EXPECT_NE(noisy["trajectory_sha256"], clean["trajectory_sha256"]) << world;
    EXPECT_EQ(again["trajectory_sha256"], noisy["trajectory_sha256"]) << world;
  }
}

TEST(LaunchRuns, AnEndlessQueueStartsAgentsAsRobotsJoinAndGivesTheInProcessTrajectory) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  // steady-influx shortened to 300 simulated seconds: 8 robots inside, 2 waiting, and a new robot
  // joining the queue every 16.6 s (ids 10, 11, ... appear as robots enter).
  const std::vector<std::string> short_influx = {scenarios + "/steady-influx.yaml", "--set", "run.duration=300"};
  const auto processes = fresh_dir("endless-processes");
  ASSERT_EQ(run_launch(processes, args(short_influx, {"--dds", vendor, "--domain", std::to_string(domain_endless)})), 0)
      << log_of(processes);
  const auto in_process = fresh_dir("endless-in-process");
  ASSERT_EQ(run_launch(in_process, args(short_influx, {"--in-process"})), 0) << log_of(in_process);
  const auto jp = read_json(processes + "/run/summary.json");
  const auto ji = read_json(in_process + "/run/summary.json");
  ASSERT_FALSE(jp.empty() || ji.empty());
  EXPECT_EQ(jp["agents"]["lost"], 0);
  // More robots than at the start had an agent: 10 at t = 0, one more per arrival.
  EXPECT_GT(ji["agents"]["started"].get<int>(), 10);
  EXPECT_GE(jp["agents"]["started"].get<int>(), ji["agents"]["started"].get<int>());
  EXPECT_EQ(jp["trajectory_sha256"], ji["trajectory_sha256"]);
}

// summary.json's `retreats` says how long robots took to drive out, and which have not got out by
// the end. steady-influx seed 7 (in process, 3 s) is a run where retreating robots jam: a robot
// that began retreating at about 97 s never leaves, and a crowd that gathers behind it near the
// boundary holds itself still under the barrier certificates (docs/experiments.md, "Retreats that never end"). The summary
// must agree with what transitions.csv records tick by tick, recounted here on its own.
TEST(LaunchRuns, TheSummaryReportsRetreatsCompletedAndStillUnderWayAsTheTransitionsRecordThem) {
  const auto dir = fresh_dir("retreats-under-way");
  ASSERT_EQ(run_launch(dir, {scenarios + "/steady-influx.yaml", "--in-process", "--seed", "7"}), 0) << log_of(dir);
  const auto j = read_json(dir + "/run/summary.json");
  ASSERT_TRUE(j.contains("retreats")) << j.dump();
  const auto& r = j["retreats"];
  // The run's "done" line names them.
  char done[128];
  std::snprintf(done, sizeof done, "optimum 4.55), %d still driving out (the longest for %.0f s), ",
                r["under_way"].get<int>(), r["longest_under_way_seconds"].get<double>());
  EXPECT_NE(log_of(dir).find(done), std::string::npos) << done << "\n" << log_of(dir);

  // The recount: phase 2 (retreating) starts a retreat, phase 3 (departed) ends it.
  std::ifstream transitions(dir + "/run/transitions.csv");
  std::string line;
  ASSERT_TRUE(std::getline(transitions, line)) << "no transitions.csv";
  std::map<int, int> phase, started;  // by robot
  std::uint64_t completed = 0;
  std::int64_t longest_completed = 0;
  while (std::getline(transitions, line)) {
    std::int64_t tick = 0;
    int robot = 0, p = 0, retreat = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%ld,%d,%d,%d", &tick, &robot, &p, &retreat), 4) << line;
    if (p == 2 && phase[robot] != 2) started[robot] = static_cast<int>(tick);
    if (p == 3 && started.count(robot) > 0) {
      ++completed;
      longest_completed = std::max<std::int64_t>(longest_completed, tick - started[robot]);
      started.erase(robot);
    }
    phase[robot] = p;
  }
  // A robot that left in the last step has no frame saying so; agents.csv's departed_at does.
  std::set<int> departed;
  std::ifstream agents(dir + "/run/agents.csv");
  ASSERT_TRUE(std::getline(agents, line)) << "no agents.csv";
  ASSERT_EQ(line.rfind("robot,agent_matched,agent_lost,lost_at,retreated,retreat_at,entered_at,departed_at,", 0), 0u);
  while (std::getline(agents, line)) {
    int robot = 0, matched = 0, lost = 0, retreated = 0;
    double lost_at = 0.0, retreat_at = 0.0, entered_at = 0.0, departed_at = -1.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%d,%lf,%d,%lf,%lf,%lf", &robot, &matched, &lost, &lost_at, &retreated,
                          &retreat_at, &entered_at, &departed_at), 8) << line;
    if (departed_at >= 0.0) departed.insert(robot);
  }
  const std::int64_t last_tick = j["ticks"].get<std::int64_t>();
  std::int64_t longest_under_way = 0;
  for (auto it = started.begin(); it != started.end();) {
    if (departed.count(it->first) > 0) {
      ++completed;
      longest_completed = std::max<std::int64_t>(longest_completed, last_tick - it->second);
      it = started.erase(it);
    } else {
      longest_under_way = std::max<std::int64_t>(longest_under_way, last_tick - it->second);
      ++it;
    }
  }
  const double dt = 0.03;  // steady-influx's agent.dt: one tick
  EXPECT_EQ(r["completed"].get<std::uint64_t>(), completed);
  EXPECT_DOUBLE_EQ(r["longest_completed_seconds"].get<double>(), static_cast<double>(longest_completed) * dt);
  EXPECT_EQ(r["under_way"].get<std::size_t>(), started.size());
  EXPECT_DOUBLE_EQ(r["longest_under_way_seconds"].get<double>(), static_cast<double>(longest_under_way) * dt);

  // The same robots as the last telemetry row's `retreating`: they are still in D.
  std::ifstream telemetry(dir + "/run/telemetry.csv");
  std::string last_row;
  for (std::string row; std::getline(telemetry, row);) last_row = row;
  int tick = 0, inside = 0, waiting = 0, retreating = -1;
  double time = 0.0;
  ASSERT_EQ(std::sscanf(last_row.c_str(), "%d,%lf,%d,%d,%d", &tick, &time, &inside, &waiting, &retreating), 5);
  EXPECT_EQ(r["under_way"].get<int>(), retreating);

  // This seed jams (a fact of its fixed trajectory, which the golden hashes pin): over 200
  // retreats end, none after more than two minutes, while more than ten robots are still driving
  // out at the end, one of them for over 20 minutes.
  EXPECT_GT(completed, 200u);
  EXPECT_LT(r["longest_completed_seconds"].get<double>(), 120.0);
  EXPECT_GT(r["under_way"].get<int>(), 10);
  EXPECT_GT(r["longest_under_way_seconds"].get<double>(), 1200.0);
}

// arena.retreat_unblock (not the paper's; random_walk.hpp, RetreatDetour): a retreating robot held
// below v/2 for arena.unblock_time leaves along a detour within 90° of its outward normal. On the
// seed whose retreats jam (above) no retreat is left stalled: every one that ended took less than
// the minute after which docs/experiments.md calls a retreat stalled, none is under way for longer
// at the end, and the swarm, no longer blocked near the boundary, delivers more.
TEST(LaunchRuns, RetreatUnblockLeavesNoRetreatStalledOnTheSeedThatJams) {
  const auto jammed = fresh_dir("retreat-unblock-off");
  ASSERT_EQ(run_launch(jammed, {scenarios + "/steady-influx.yaml", "--in-process", "--seed", "7"}), 0) << log_of(jammed);
  const auto unblocked = fresh_dir("retreat-unblock-on");
  ASSERT_EQ(run_launch(unblocked, {scenarios + "/steady-influx.yaml", "--in-process", "--seed", "7", "--set",
                                   "arena.retreat_unblock=true"}),
            0) << log_of(unblocked);
  const auto off = read_json(jammed + "/run/summary.json");
  const auto on = read_json(unblocked + "/run/summary.json");
  ASSERT_TRUE(off.contains("retreats") && on.contains("retreats")) << on.dump();
  const double stalled_after = 60.0;  // experiment::stalled_retreat_after
  ASSERT_GT(off["retreats"]["longest_under_way_seconds"].get<double>(), stalled_after) << "seed 7 no longer jams";
  EXPECT_GT(on["retreats"]["completed"].get<int>(), 200);
  EXPECT_LT(on["retreats"]["longest_completed_seconds"].get<double>(), stalled_after);
  EXPECT_LT(on["retreats"]["longest_under_way_seconds"].get<double>(), stalled_after);
  EXPECT_GT(on["deliveries"].get<int>(), off["deliveries"].get<int>());
  EXPECT_NE(on["trajectory_sha256"], off["trajectory_sha256"]);
}

TEST(LaunchRuns, RealTimeModePassesThrough) {
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto dir = fresh_dir("realtime");
  // 3 simulated seconds at 3x: one wall second of ticks.
  ASSERT_EQ(run_launch(dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain_realtime),
                             "--set", "run.mode=realtime", "--set", "run.duration=3", "--set", "run.speed=3"}),
            0) << log_of(dir);
  const auto j = read_json(dir + "/run/summary.json");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["mode"], "realtime");
  EXPECT_GE(j["ticks"].get<int>(), 100);  // 3 s / 0.03 s (the last tick may round up)
  EXPECT_LE(j["ticks"].get<int>(), 101);
  EXPECT_EQ(j["agents"]["started"], 12);
  EXPECT_EQ(j["agents"]["lost"], 0);
}

TEST(LaunchRuns, TheBridgeIsStartedBesideTheSwarmAndStoppedAfterIt) {
  if (::access(bridge_program.c_str(), X_OK) != 0) GTEST_SKIP() << "retreat-bridge is not built";
  const std::string vendor = built("cyclonedds") ? "cyclonedds" : "fastdds";
  const auto dir = fresh_dir("bridge");
  ASSERT_EQ(run_launch(dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain_bridge),
                             "--set", "run.duration=100", "--set", "bridge.http=127.0.0.1:0"},
                       retreat::testing::hang_ceiling, /*bridge=*/true), 0) << log_of(dir);
  const auto j = read_json(dir + "/run/summary.json");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["launch"]["bridge"], true);
  const auto processes = read_json(dir + "/run/processes.json");
  ASSERT_FALSE(processes["bridge"].is_null());
  EXPECT_TRUE(alive(child_pids(processes)).empty());
  EXPECT_TRUE(std::filesystem::exists(dir + "/run/logs/bridge.log"));
}

// A Cyclone star (deploy/dds/cyclonedds-star-*.xml): agents announce to participant indices 0
// (the hub, the arena), 1 and 2 only, so the launcher runs the bridge on the hub's file as index 1;
// otherwise it would hear no agent. Every robot's status reaching agent_status.csv proves it.
// The full 1,200 s with K_p = λ_in = 0 (nobody retreats, every agent runs to the end): some 10 s
// of wall time, several of Cyclone's 2 s discovery announcements, even on a loaded machine.
TEST(LaunchRuns, InACycloneStarTheBridgeHearsEveryAgent) {
  if (!built("cyclonedds")) GTEST_SKIP() << "needs Cyclone DDS";
  if (::access(bridge_program.c_str(), X_OK) != 0) GTEST_SKIP() << "retreat-bridge is not built";
  const std::string profiles = std::string(RETREAT_PROFILES) + "/";
  const auto dir = fresh_dir("cyclone-star-bridge");
  ASSERT_EQ(run_launch(dir, {robotarium, "--dds", "cyclonedds", "--domain", std::to_string(domain_cyclone_star),
                             "--arena-profile", profiles + "cyclonedds-star-hub.xml", "--set",
                             "dds.profile=" + profiles + "cyclonedds-star-agent.xml", "--set", "agent.K_p=0",
                             "--set", "agent.lambda_in=0", "--set", "bridge.http=127.0.0.1:0",
                             // 300 s (10,000 ticks) is ample: every agent publishes its status
                             // every run.status_period, and the status topic keeps each agent's
                             // last one for a bridge that matches late (transient local).
                             "--set", "run.duration=300",
                             // Per tick: with plans the run ends within a second, before a
                             // late-matching bridge has heard every agent, whose statuses go
                             // with it (a star's discovery, not the bridge, is what is tested).
                             "--set", "run.plans=false"},
                       retreat::testing::hang_ceiling, /*bridge=*/true), 0) << log_of(dir);
  std::ifstream statuses(dir + "/run/agent_status.csv");
  ASSERT_TRUE(statuses.good()) << log_of(dir);
  std::string line;
  std::getline(statuses, line);  // header: time,robot,...
  std::set<int> robots;
  while (std::getline(statuses, line)) {
    const auto first = line.find(',');
    if (first != std::string::npos) robots.insert(std::stoi(line.substr(first + 1)));
  }
  EXPECT_EQ(robots.size(), 12U) << "robots heard by the bridge: " << robots.size();
}

// Event-driven lockstep (run.plans) over real DDS processes, each vendor and mixed: the 1,200 s
// robotarium run (40,000 ticks, robots retreating) has the per-tick in-process trajectory, with
// a few hundred answers instead of one per robot per tick. Every controller, scenario and both
// queues in one process: tests/scenario/plans_equivalence_test.cpp.
TEST(LaunchRuns, PlansOverFastDdsCycloneDdsAndMixedGiveThePerTickTrajectoryWithFewAnswers) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const auto in_process = fresh_dir("plans-in-process");
  ASSERT_EQ(run_launch(in_process, {robotarium, "--in-process", "--set", "run.plans=false"}), 0) << log_of(in_process);
  const auto per_tick = read_json(in_process + "/run/summary.json");
  ASSERT_FALSE(per_tick.empty()) << log_of(in_process);
  int domain = testing::domains::launch_plans.first;
  for (const char* vendor : {"fastdds", "cyclonedds", "mixed"}) {
    const auto dir = fresh_dir(std::string("plans-") + vendor);
    ASSERT_EQ(run_launch(dir, {robotarium, "--dds", vendor, "--domain", std::to_string(domain++), "--set",
                               "run.plans=true"}),
              0)
        << log_of(dir);
    const auto j = read_json(dir + "/run/summary.json");
    ASSERT_FALSE(j.empty()) << log_of(dir);
    EXPECT_EQ(j["trajectory_sha256"], per_tick["trajectory_sha256"]) << vendor;
    EXPECT_EQ(j["agents"]["lost"], 0) << vendor;
    EXPECT_GT(j["agents"]["retreated"].get<int>(), 0) << vendor;
    // Per tick, every robot answers every tick (some 124,000 answers); with plans, a robot is
    // asked only when its input changes or its plan (500 ticks at most) ends.
    EXPECT_LT(j["decisions_received"].get<std::uint64_t>(), per_tick["decisions_received"].get<std::uint64_t>() / 20)
        << vendor;
    EXPECT_GT(j["decisions_planned"].get<std::uint64_t>(), j["decisions_received"].get<std::uint64_t>()) << vendor;
  }
}

// More agent processes than one domain's block of well-known ports holds (participant indices
// 0..119, which is why the built-in settings stop at 120: LaunchInput's capacity test): 130
// agents in a Cyclone star, where agents take free ports and only the arena has an index. Every
// agent matched, none lost, and the trajectory (with retreats: L = 3 s, K_p = 5) is the in-process
// one. kinetic-1000 at its density on 9 m × 9 m, 6 s (200 ticks): some 15 s of wall time.
TEST(LaunchRuns, ACycloneStarOf130AgentsBeyondOnePortBlockCompletesWithNoneLostAndTheInProcessTrajectory) {
  if (!built("cyclonedds")) GTEST_SKIP() << "needs Cyclone DDS";
  const std::string profiles = std::string(RETREAT_PROFILES) + "/";
  const std::vector<std::string> scenario = {scenarios + "/kinetic-1000.yaml", "--set", "arena.robots_inside=130",
                                             "--set", "arena.width=9", "--set", "arena.height=9", "--set",
                                             "run.duration=6", "--set", "agent.L=3", "--set", "agent.K_p=5"};
  const auto star = fresh_dir("cyclone-star-130");
  ASSERT_EQ(run_launch(star, args(scenario, {"--dds", "cyclonedds", "--domain",
                                             std::to_string(testing::domains::launch_star.at(0)), "--arena-profile",
                                             profiles + "cyclonedds-star-hub.xml", "--set",
                                             "dds.profile=" + profiles + "cyclonedds-star-agent.xml"})),
            0)
      << log_of(star);
  const auto in_process = fresh_dir("cyclone-star-130-in-process");
  ASSERT_EQ(run_launch(in_process, args(scenario, {"--in-process"})), 0) << log_of(in_process);
  const auto s = read_json(star + "/run/summary.json");
  EXPECT_EQ(s.at("agents").at("started"), 130) << log_of(star);
  EXPECT_EQ(s.at("agents").at("matched"), 130) << log_of(star);
  EXPECT_EQ(s.at("agents").at("lost"), 0) << log_of(star);
  EXPECT_GT(s.at("agents").at("retreated").get<int>(), 0) << "the run exercises decisions";
  EXPECT_EQ(s.at("trajectory_sha256"), read_json(in_process + "/run/summary.json").at("trajectory_sha256"));
  // Domain 101's well-known ports (32650..32899) reach Linux's default ephemeral range (32768..):
  // the launcher says so at start-up in one line, with the way out. On a host whose range starts
  // higher it says nothing: the line is checked against this host's range either way.
  const auto log = log_of(star);
  const auto warning = launch::ephemeral_port_warning(testing::domains::launch_star.at(0), 1,
                                                      launch::read_ephemeral_ports());
  if (warning) {
    EXPECT_NE(log.find("retreat-launch: warning: " + *warning + "\n"), std::string::npos) << log;
  } else {
    EXPECT_EQ(log.find("ephemeral"), std::string::npos) << log;
  }
  EXPECT_EQ(log.find("ephemeral"), log.rfind("ephemeral")) << "one warning line: " << log;
}

}  // namespace
}  // namespace retreat::launch_test
