// Density regulation, measured: the rules of issue 14 hold the population near the optimum
// λ*·|D| where `paper` does not, on fixed seeds of the shipped scenarios (kinetic world, the
// launcher in process). The full 100-seed measurements, in the physical world too, are in
// docs/experiments.md ("Rules that reach the optimum").
//
// Tolerance: over 100 seeds the mean of the last 300 s has a standard deviation between seeds
// of 0.65 (confident-proportional, finite queue) and 0.82 (influx-matching, endless queue), so
// the mean of these 20 seeds has a standard error of at most 0.82/√20 = 0.18 robots. The check
// allows 0.6 robots (3.3 standard errors) around the optimum 4.55, which `paper` misses by 2.8
// (finite queue) and 4.2 (endless queue) robots. The seeds are fixed: the verdict is the same
// on every run; the tolerance is what a correct change of the world or the rule may move it.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "retreat/testing/process.hpp"

namespace {

constexpr double tolerance = 0.6;  // robots; see above

struct Sweep {
  double mean_last_300s = 0.0;
  double optimum = 0.0;
  int seeds = 0;
};

Sweep sweep(const std::string& scenario, const std::string& controller, const std::vector<std::string>& overrides = {}) {
  const std::string out = ::testing::TempDir() + "/regulation_" + scenario + "_" + controller;
  std::filesystem::remove_all(out);
  std::vector<std::string> argv = {RETREAT_LAUNCH_BIN, std::string(RETREAT_SCENARIOS) + "/" + scenario + ".yaml",
                                   "--in-process", "--no-bridge", "--seeds", "1:20", "--out", out,
                                   "--set", "arena.encounter_model=kinetic", "--set",
                                   "agent.controller=" + controller};
  for (const auto& o : overrides) argv.insert(argv.end(), {"--set", o});
  retreat::testing::ChildProcess launch(argv, out + ".log");
  const auto code = launch.wait_for(retreat::testing::hang_ceiling);
  EXPECT_EQ(code.value_or(-1), 0) << retreat::testing::read_file(out + ".log");
  Sweep s;
  std::ifstream in(out + "/seeds_summary.json");
  if (!in) return s;
  const auto j = nlohmann::json::parse(in);
  s.mean_last_300s = j.at("population").at("mean_last_300s").at("mean").get<double>();
  s.seeds = j.at("seeds").get<int>();
  std::ifstream first(out + "/seed_1/summary.json");
  s.optimum = nlohmann::json::parse(first).at("optimal_population").get<double>();
  std::filesystem::remove_all(out);
  std::filesystem::remove(out + ".log");
  return s;
}

TEST(Regulation, ConfidentProportionalHoldsTheFiniteQueueNearTheOptimumWherePaperDrainsIt) {
  const auto rule = sweep("robotarium-2019", "confident-proportional");
  const auto paper = sweep("robotarium-2019", "paper");
  ASSERT_EQ(rule.seeds, 20);
  ASSERT_EQ(paper.seeds, 20);
  EXPECT_NEAR(rule.optimum, 4.55, 0.01);
  EXPECT_NEAR(rule.mean_last_300s, rule.optimum, tolerance);
  EXPECT_LT(paper.mean_last_300s, rule.optimum - tolerance);
}

TEST(Regulation, InfluxMatchingHoldsTheEndlessQueueNearTheOptimumWherePaperOvershoots) {
  const auto rule = sweep("steady-influx", "influx-matching");
  const auto paper = sweep("steady-influx", "paper");
  ASSERT_EQ(rule.seeds, 20);
  ASSERT_EQ(paper.seeds, 20);
  EXPECT_NEAR(rule.mean_last_300s, rule.optimum, tolerance);
  EXPECT_GT(paper.mean_last_300s, rule.optimum + tolerance);
}

// The cells of the sweep where confident-proportional falls more than 10 % below the optimum
// (docs/experiments.md, "The sweep"): a gain four times the paper's, and a 20 m² rectangle with
// 60 robots. adaptive-proportional holds both. Tolerances: 0.6 robots around 4.55 as above; for
// the rectangle (N* = 30.15, a spread between seeds of about 1.5, so a standard error of 0.34
// for 20 seeds) the aim of issue 14 itself, 10 % of N*, which is about 9 standard errors.
TEST(Regulation, AdaptiveProportionalHoldsTheFiniteQueueWithAFasterGainAndInALargerArena) {
  const auto fast = sweep("robotarium-2019", "adaptive-proportional", {"agent.K_p=0.1"});
  ASSERT_EQ(fast.seeds, 20);
  EXPECT_NEAR(fast.mean_last_300s, fast.optimum, tolerance);
  const auto large = sweep("robotarium-2019", "adaptive-proportional",
                           {"arena.shape=rectangle", "arena.width=5.0", "arena.height=4.0", "arena.robots_inside=50",
                            "arena.robots_waiting=10"});
  ASSERT_EQ(large.seeds, 20);
  EXPECT_NEAR(large.optimum, 30.15, 0.01);
  EXPECT_NEAR(large.mean_last_300s, large.optimum, 0.1 * large.optimum);
}

}  // namespace
