// report.html from a scripted run directory: the plotted numbers are exact, several seed
// directories give a mean and a band, and the page is self-contained.

#include "retreat/report/report.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "retreat/model/ctmc.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::report {
namespace {

namespace fs = std::filesystem;

const std::string yaml =
    "name: report-test\nseed: 1\n"
    "arena: {encounter_model: kinetic, robots_inside: 4, robots_waiting: 0}\n"
    "run: {duration: 100}\n";

double area() {
  // The default ellipse, 1.2 m x 0.8 m semi-axes.
  return 3.14159265358979323846 * 1.2 * 0.8;
}

/// A run directory with 100 telemetry rows (t = 0..99 s): `before` robots inside until t = 50,
/// `after` from then on; a delivery every 2 s.
void write_run(const std::string& dir, int before, int after, int seed) {
  fs::create_directories(dir);
  std::ofstream(dir + "/scenario.yaml") << scenario::dump(scenario::parse(yaml));
  std::ofstream t(dir + "/telemetry.csv");
  t << "tick,time,inside,waiting,retreating,departed,true_density,deliveries,onsets,free,loaded,"
       "free_colliding,loaded_colliding\n";
  t.precision(17);
  for (int k = 0; k < 100; ++k) {
    const int inside = k < 50 ? before : after;
    t << k * 33 << ',' << k << ',' << inside << ",0,0,0," << inside / area() << ',' << k / 2
      << ",0,0,0,0,0\n";
  }
  std::ofstream(dir + "/summary.json") << "{\"seed\": " << seed << ", \"ticks\": 3300}\n";
}

class Report : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/report_" + ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
  }
  std::string dir_;
};

TEST_F(Report, PlotsTheRunsPopulationThroughputEncountersAndEstimates) {
  write_run(dir_, 4, 2, 1);
  std::ofstream(dir_ + "/encounters.csv") << "robot,other,onset_time,end_time\n"
                                          << "0,1,10,11\n0,2,20,21\n1,2,40,41\n"
                                          << "0,4294967295,10,11\n";  // an episode: not an onset
  std::ofstream(dir_ + "/agent_status.csv") << "time,robot,tick,deciding,retreating,onsets_in_window,lambda_hat,epsilon\n"
                                            << "10.2,0,309,1,0,5,1.0,0\n10.4,1,315,1,0,5,2.0,0\n"
                                            << "10.6,2,321,0,0,5,9.0,0\n";
  const auto j = report_data(dir_);
  EXPECT_EQ(j["title"], "report-test");
  EXPECT_EQ(j["runs"].size(), 1u);
  EXPECT_EQ(j["runs"][0]["summary"]["seed"], 1);
  // Population: 100 points on t = 0..99.
  const auto& p = j["population"];
  ASSERT_EQ(p["time"].size(), 100u);
  EXPECT_DOUBLE_EQ(p["time"][49].get<double>(), 49.0);
  EXPECT_DOUBLE_EQ(p["mean"][49].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(p["mean"][50].get<double>(), 2.0);
  EXPECT_EQ(p["seeds"], 1);
  // Throughput: windows of max(99/30, 20) = 20 s starting at 0, 20, 40, 60 (80 + 20 > 99);
  // the first averages rows t = 0..19 (4 robots) and counts 10 deliveries from t = 0 to 20;
  // the third averages 4 robots for 10 rows and 2 for 10.
  const auto& t = j["throughput"];
  EXPECT_DOUBLE_EQ(t["window"].get<double>(), 20.0);
  ASSERT_EQ(t["points"].size(), 4u);
  EXPECT_DOUBLE_EQ(t["points"][0][0].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(t["points"][0][1].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(t["points"][2][0].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(t["points"][3][0].get<double>(), 2.0);
  const auto s = scenario::parse(yaml);
  const auto& curve = t["curve"];
  EXPECT_DOUBLE_EQ(curve[0][1].get<double>(), 0.0);
  const double n = curve[60][0].get<double>();
  EXPECT_NEAR(curve[60][1].get<double>(), model::output(s.model, n / area()) * area(),
              1e-5 * model::output(s.model, n / area()) * area());
  // Encounters: onsets per robot 0: 10, 20; 1: 10, 40; 2: 20, 40 -> gaps 10, 30, 20.
  const auto& e = j["encounters"];
  ASSERT_FALSE(e.is_null());
  EXPECT_EQ(e["gaps"], 3);
  EXPECT_DOUBLE_EQ(e["mean_gap"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(e["fitted_rate"].get<double>(), 0.05);
  const double mean_density = (50 * 4 + 49 * 2) / (99 * area());
  EXPECT_NEAR(e["model_rate"].get<double>(), model::omega_c(s.model, mean_density), 1e-5);
  EXPECT_EQ(e["bins"].size(), 30u);
  // Estimates: 1 s bins; bin 10 holds 1.0 and 2.0 (robot 2 was not deciding).
  const auto& est = j["estimates"];
  ASSERT_FALSE(est.is_null());
  EXPECT_EQ(est["agents"], 2);
  EXPECT_DOUBLE_EQ(est["time"][10].get<double>(), 10.5);
  EXPECT_DOUBLE_EQ(est["mean"][10].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(est["low"][10].get<double>(), 1.1);
  EXPECT_DOUBLE_EQ(est["high"][10].get<double>(), 1.9);
  EXPECT_TRUE(est["mean"][9].is_null());
  EXPECT_NEAR(est["true_density"][10].get<double>(), 4 / area(), 1e-5);
}

TEST_F(Report, SeveralSeedDirectoriesGiveTheMeanAndTheBand) {
  write_run(dir_ + "/seed_2", 6, 0, 2);
  write_run(dir_ + "/seed_1", 4, 2, 1);
  fs::create_directories(dir_ + "/seed_3");  // no telemetry: not a run
  std::ofstream(dir_ + "/seed_1/encounters.csv") << "robot,other,onset_time,end_time\n0,1,10,11\n";
  const auto j = report_data(dir_);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_EQ(j["runs"][0]["dir"], "seed_1");
  EXPECT_EQ(j["runs"][1]["dir"], "seed_2");
  const auto& p = j["population"];
  EXPECT_EQ(p["seeds"], 2);
  EXPECT_DOUBLE_EQ(p["mean"][10].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(p["min"][10].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(p["max"][10].get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(p["mean"][60].get<double>(), 1.0);
  // One encounter: no gap between onsets, nothing to histogram.
  EXPECT_EQ(j["encounters"]["gaps"], 0);
  EXPECT_TRUE(j["encounters"]["bins"].is_null());
  EXPECT_TRUE(j["estimates"].is_null());
}

TEST_F(Report, IsOneSelfContainedPage) {
  write_run(dir_, 4, 2, 1);
  const auto path = write_report(dir_);
  EXPECT_EQ(path, dir_ + "/report.html");
  std::ifstream in(path);
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(html.rfind("<!doctype html>", 0), 0u);
  EXPECT_NE(html.find("window.REPORT = {"), std::string::npos);
  EXPECT_NE(html.find("uPlot"), std::string::npos);
  // Nothing loaded from elsewhere: no external scripts, styles or links.
  for (const char* external : {"<script src", "<link", "src=\"http", "href=\"http", "@import"}) {
    EXPECT_EQ(html.find(external), std::string::npos) << external;
  }
  std::size_t closes = 0;
  for (auto at = html.find("</script>"); at != std::string::npos; at = html.find("</script>", at + 1)) ++closes;
  EXPECT_EQ(closes, 3u);
  EXPECT_FALSE(fs::exists(dir_ + "/report.html.tmp"));
}

TEST_F(Report, ADirectoryWithoutTelemetryIsRefused) {
  fs::create_directories(dir_);
  EXPECT_THROW((void)report_data(dir_), std::runtime_error);
}

// A directory where a run's file belongs: telemetry.csv is refused in one line naming it (its
// first read threw a stream error naming nothing: "basic_filebuf::underflow error reading the
// file"), and summary.json counts as missing, as for a run still being written.
TEST_F(Report, ADirectoryInPlaceOfARunsFileIsNamedOrCountsAsMissing) {
  write_run(dir_, 4, 2, 1);
  fs::remove(dir_ + "/summary.json");
  fs::create_directories(dir_ + "/summary.json");
  const auto j = report_data(dir_);
  ASSERT_EQ(j["runs"].size(), 1u);
  EXPECT_TRUE(j["runs"][0]["summary"].is_null());

  fs::remove(dir_ + "/telemetry.csv");
  fs::create_directories(dir_ + "/telemetry.csv");
  try {
    (void)report_data(dir_);
    ADD_FAILURE() << "a directory as telemetry.csv was read";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), dir_ + "/telemetry.csv: cannot read it as a file");
  }
}

}  // namespace
}  // namespace retreat::report
