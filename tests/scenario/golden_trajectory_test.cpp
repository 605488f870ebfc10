// Golden trajectories: the shipped Robotarium scenario, seed 1, run in process by the launcher,
// gives exactly the recorded decisions, for the paper's controller in both worlds and for every
// other named controller (tests/scenario/golden_hashes.json, one case each). A change to the
// algorithm, the estimator, the seeding, the generators or the world that alters any decision
// changes a hash and fails here; such a change must be deliberate and the hashes re-recorded in
// the same commit, with the reason. The same hashes come out of the multi-process runs over
// Fast DDS, Cyclone DDS and mixed (tests/integration/launch_runs_test) and, read as JSON, out of
// a Clang + libc++ build (tests/portability, run by deploy/test.sh).
//
// Recorded with: retreat-launch deploy/scenarios/robotarium-2019.yaml --in-process [--set ...]
// Last re-recorded when the agent's coin became counter_uniform(key, step k) (issue 12): the
// std::uniform_real_distribution over std::mt19937_64 it replaced gave other values with libc++.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "retreat/scenario/json.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/testing/process.hpp"

namespace {

const std::string robotarium = std::string(RETREAT_SCENARIOS) + "/robotarium-2019.yaml";

nlohmann::json golden_cases() {
  std::ifstream in(RETREAT_GOLDEN_HASHES);
  return nlohmann::json::parse(in).at("cases");
}

std::vector<std::string> overrides_of(const nlohmann::json& c) {
  return c.at("set").get<std::vector<std::string>>();
}

nlohmann::json run_in_process(const std::string& name, const std::vector<std::string>& overrides) {
  const std::string out = ::testing::TempDir() + "/golden_" + name;
  std::filesystem::remove_all(out);
  std::vector<std::string> argv = {RETREAT_LAUNCH_BIN, robotarium, "--in-process", "--no-bridge", "--out", out};
  for (const auto& o : overrides) argv.insert(argv.end(), {"--set", o});
  retreat::testing::ChildProcess launch(argv, out + ".log");
  const auto code = launch.wait_for(retreat::testing::hang_ceiling);
  EXPECT_EQ(code.value_or(-1), 0) << retreat::testing::read_file(out + ".log");
  std::ifstream in(out + "/summary.json");
  return in.good() ? nlohmann::json::parse(in) : nlohmann::json{};
}

class GoldenTrajectory : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenTrajectory, TheLauncherInProcessDecidesExactlyAsRecorded) {
  for (const auto& c : golden_cases()) {
    if (c.at("name") != GetParam()) continue;
    const auto j = run_in_process(GetParam(), overrides_of(c));
    ASSERT_FALSE(j.empty());
    EXPECT_EQ(j["controller"], c.at("controller"));
    EXPECT_EQ(j["ticks"], c.at("ticks"));  // fewer than 40,000 where every robot left early
    EXPECT_EQ(j["agents"]["retreated"], c.at("retreated"));
    EXPECT_EQ(j["trajectory_sha256"], c.at("trajectory_sha256"));
    return;
  }
  FAIL() << "no case " << GetParam();
}

// The portability check reads each case's resolved scenario as JSON: it must be exactly what
// the YAML scenario with the case's overrides resolves to (written to the build tree when not,
// to be copied into tests/portability/scenarios after a deliberate change).
TEST_P(GoldenTrajectory, ThePortabilityChecksJsonScenarioIsTheYamlOneResolved) {
  for (const auto& c : golden_cases()) {
    if (c.at("name") != GetParam()) continue;
    const auto expected = retreat::scenario::dump_json(retreat::scenario::load(robotarium, overrides_of(c)));
    const auto committed = retreat::testing::read_file(std::string(RETREAT_PORTABILITY_SCENARIOS) + "/" +
                                                       GetParam() + ".json");
    if (committed != expected) {
      const auto path = ::testing::TempDir() + "/" + GetParam() + ".json";
      std::ofstream(path) << expected;
      ADD_FAILURE() << "tests/portability/scenarios/" << GetParam() << ".json differs from the YAML "
                    << "scenario resolved; the resolved one is in " << path;
    }
    return;
  }
  FAIL() << "no case " << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Case, GoldenTrajectory,
                         ::testing::Values("paper-physical", "paper-kinetic", "confident", "influx-aware",
                                           "confident-influx-aware", "confident-proportional",
                                           "influx-matching", "adaptive-proportional"),
                         [](const auto& test) {
                           std::string name = test.param;
                           for (auto& ch : name) ch = ch == '-' ? '_' : ch;
                           return name;
                         });

TEST(GoldenTrajectory, EveryRecordedControllerDecidesUnlikePaper) {
  std::string paper;
  for (const auto& c : golden_cases()) {
    if (c.at("name") == "paper-physical") paper = c.at("trajectory_sha256");
  }
  ASSERT_FALSE(paper.empty());
  for (const auto& c : golden_cases()) {
    if (c.at("controller") != "paper") {
      EXPECT_NE(c.at("trajectory_sha256"), paper) << c.at("name");
    }
  }
}

}  // namespace
