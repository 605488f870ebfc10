// Golden trajectories: the paper's controller on the shipped Robotarium scenario, seed 1, gives
// exactly these decisions, and it still does with the other named controllers registered beside
// it (its hash was recorded before they existed). The other controllers are pinned the same way. A change to the algorithm, the estimator, the seeding or the world
// that alters any decision changes the hash and fails here; such a change must be deliberate
// and the hashes re-recorded in the same commit, with the reason.
//
// Recorded with: retreat-launch deploy/scenarios/robotarium-2019.yaml --in-process
//                [--set arena.encounter_model=kinetic]; the same hashes come out of the
// multi-process runs over Fast DDS, Cyclone DDS and mixed (tests/integration/launch_runs_test).

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <utility>
#include <vector>
#include <nlohmann/json.hpp>

#include "retreat/testing/process.hpp"

namespace {

using namespace std::chrono_literals;

nlohmann::json run_in_process(const std::string& tag, const std::vector<std::string>& extra) {
  const std::string out = ::testing::TempDir() + "/golden_" + tag;
  std::vector<std::string> argv = {RETREAT_LAUNCH_BIN, std::string(RETREAT_SCENARIOS) + "/robotarium-2019.yaml",
                                   "--in-process", "--no-bridge", "--out", out};
  argv.insert(argv.end(), extra.begin(), extra.end());
  retreat::testing::ChildProcess launch(argv, out + ".log");
  const auto code = launch.wait_for(retreat::testing::hang_ceiling);
  EXPECT_EQ(code.value_or(-1), 0) << retreat::testing::read_file(out + ".log");
  std::ifstream in(out + "/summary.json");
  return in.good() ? nlohmann::json::parse(in) : nlohmann::json{};
}

TEST(GoldenTrajectory, ThePaperControllerInThePhysicalWorldDecidesExactlyAsRecorded) {
  const auto j = run_in_process("physical", {});
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["controller"], "paper");
  EXPECT_EQ(j["ticks"], 40000);
  EXPECT_EQ(j["agents"]["retreated"], 9);
  EXPECT_EQ(j["trajectory_sha256"], "3be7e02c4784b848d2eea1ebb685a62996e608684d60cc30dea443787c9a5775");
}

TEST(GoldenTrajectory, ThePaperControllerInTheKineticWorldDecidesExactlyAsRecorded) {
  const auto j = run_in_process("kinetic", {"--set", "arena.encounter_model=kinetic"});
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["agents"]["retreated"], 10);
  EXPECT_EQ(j["trajectory_sha256"], "ecaf0f46231bf053d5bbf666ce3bb7918d9d004501126e92ab72ca3ad848a830");
}

// The improved controllers (agent/core, docs/experiments.md), recorded when they were added.
TEST(GoldenTrajectory, EveryOtherNamedControllerDecidesExactlyAsRecorded) {
  const std::vector<std::pair<std::string, std::string>> recorded = {
      {"confident", "b53727c777bc1cdde85310d209b043c807b9e7a38050a01c0da67fe503e0a65e"},
      {"influx-aware", "8f337b7af68924c528d04e7b4b561094890fe0f94b08244976316f0ba25f373f"},
      {"confident-influx-aware", "12c8e998de4fae7f4d293e5468c4f1c7d2e168a9b1f280cc31dd77ff0c1508c8"},
  };
  for (const auto& [controller, hash] : recorded) {
    const auto j = run_in_process(controller, {"--set", "agent.controller=" + controller});
    ASSERT_FALSE(j.empty()) << controller;
    EXPECT_EQ(j["controller"], controller);
    EXPECT_EQ(j["trajectory_sha256"], hash) << controller;
    EXPECT_NE(j["trajectory_sha256"], "3be7e02c4784b848d2eea1ebb685a62996e608684d60cc30dea443787c9a5775")
        << controller << " decides exactly like paper";
  }
}

}  // namespace
