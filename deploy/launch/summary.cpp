#include "summary.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace retreat::launch {
namespace {

/// Mean and sample standard deviation (n − 1; 0 for a single value).
nlohmann::json mean_std(const std::vector<double>& values) {
  double mean = 0.0;
  for (const double v : values) mean += v;
  mean = values.empty() ? 0.0 : mean / static_cast<double>(values.size());
  double ss = 0.0;
  for (const double v : values) ss += (v - mean) * (v - mean);
  const double sd = values.size() > 1 ? std::sqrt(ss / static_cast<double>(values.size() - 1)) : 0.0;
  return {{"mean", mean}, {"std", sd}, {"n", values.size()}};
}

double number_at(const nlohmann::json& j, const nlohmann::json::json_pointer& p) {
  return j.contains(p) && j.at(p).is_number() ? j.at(p).get<double>() : std::nan("");
}

}  // namespace

void write_json_atomically(const std::string& path, const nlohmann::json& j) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << '\n';
    if (!out.flush()) throw std::runtime_error("cannot write '" + tmp + "'");
  }
  std::filesystem::rename(tmp, path);
}

nlohmann::json update_summary(const std::string& dir, const LaunchRecord& r) {
  const std::string path = dir + "/summary.json";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("the arena wrote no summary: '" + path + "' is missing");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("'" + path + "' is not valid JSON: " + e.what());
  }
  j["dds"] = r.dds;
  // The arena counts the agents it matched at start; the launcher counts what it started.
  if (j.contains("agents") && j["agents"].contains("started")) {
    j["agents"]["matched"] = j["agents"]["started"];
  }
  j["agents"]["started"] = r.agents_started;
  nlohmann::json launch;
  launch["mode"] = r.mode;
  launch["wall_seconds"] = r.wall_seconds;
  if (r.domain >= 0) launch["domain"] = r.domain;
  launch["arena_vendor"] = r.arena_vendor;
  launch["agent_vendors"] = r.agent_vendors;
  launch["bridge"] = r.bridge;
  if (r.bridge) launch["bridge_restarts"] = r.bridge_restarts;
  if (r.mode == "processes") launch["arena_restarts"] = r.arena_restarts;
  if (r.seconds_to_first_tick >= 0) launch["seconds_to_first_tick"] = r.seconds_to_first_tick;
  if (r.children_user_seconds >= 0) {
    launch["cpu_seconds"] = {{"user", r.children_user_seconds}, {"system", r.children_system_seconds}};
  }
  if (!r.recording.empty()) {
    launch["recording"] = {{"file", r.recording}, {"recorder", r.recorder_exit}};
  }
  j["launch"] = launch;
  write_json_atomically(path, j);
  return j;
}

nlohmann::json write_seeds_summary(const std::string& out_dir, const std::vector<nlohmann::json>& summaries) {
  using ptr = nlohmann::json::json_pointer;
  nlohmann::json j;
  std::vector<double> final_pop, mean_pop, deliveries, lost, tps;
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& s : summaries) {
    final_pop.push_back(number_at(s, ptr("/population/final")));
    mean_pop.push_back(number_at(s, ptr("/population/mean_last_300s")));
    deliveries.push_back(number_at(s, ptr("/deliveries")));
    lost.push_back(number_at(s, ptr("/agents/lost")));
    tps.push_back(number_at(s, ptr("/ticks_per_second")));
    runs.push_back({{"seed", s.value("seed", 0)},
                    {"population_final", s.value(ptr("/population/final"), 0)},
                    {"population_mean_last_300s", s.value(ptr("/population/mean_last_300s"), 0.0)},
                    {"deliveries", s.value("deliveries", 0)},
                    {"agents_lost", s.value(ptr("/agents/lost"), 0)},
                    {"retreats_under_way", s.value(ptr("/retreats/under_way"), 0)},
                    {"longest_retreat_under_way_seconds", s.value(ptr("/retreats/longest_under_way_seconds"), 0.0)},
                    {"ticks", s.value("ticks", 0)},
                    {"trajectory_sha256", s.value("trajectory_sha256", std::string())}});
  }
  if (!summaries.empty()) {
    const auto& s0 = summaries.front();
    j["scenario"] = s0.value("scenario", std::string());
    j["dds"] = s0.value("dds", std::string());
    j["lambda_star"] = s0.value("lambda_star", 0.0);
    j["optimal_population"] = s0.value("optimal_population", 0.0);
  }
  j["seeds"] = summaries.size();
  j["population"]["final"] = mean_std(final_pop);
  j["population"]["mean_last_300s"] = mean_std(mean_pop);
  j["deliveries"] = mean_std(deliveries);
  j["agents_lost"] = mean_std(lost);
  j["ticks_per_second"] = mean_std(tps);
  j["runs"] = runs;
  write_json_atomically(out_dir + "/seeds_summary.json", j);
  return j;
}

}  // namespace retreat::launch
