#include "ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "page.hpp"

namespace retreat::experiment {

Ensemble run_ensemble(const std::string& launcher, const std::string& name, const std::string& label,
                      const LaunchRequest& request, double C) {
  run_launch(launcher, request);
  Ensemble e;
  e.name = name;
  e.label = label;
  e.runs = read_seed_runs(request.out, C, population_grid, worker_count(request.jobs));
  std::size_t points = 0;
  for (const auto& r : e.runs) points = std::max(points, r.population.size());
  for (std::size_t k = 0; k < points; ++k) {
    std::vector<double> at;
    for (const auto& r : e.runs) {
      if (k < r.population.size()) at.push_back(r.population[k]);
    }
    const auto m = moments(at);
    e.time.push_back(population_grid * static_cast<double>(k));
    e.mean.push_back(m.mean);
    e.sd.push_back(m.sd);
    e.min.push_back(m.min);
    e.max.push_back(m.max);
  }
  return e;
}

Moments over_seeds(const Ensemble& e, double (*value)(const SeedRun&)) {
  std::vector<double> v;
  for (const auto& r : e.runs) v.push_back(value(r));
  return moments(v);
}

nlohmann::json population_figure(const Ensemble& e, const std::string& id, const std::string& title) {
  const double optimum = e.runs.front().optimal_population;
  const auto final_pop = over_seeds(e, [](const SeedRun& r) { return r.final_population; });
  const auto last300 = over_seeds(e, [](const SeedRun& r) { return r.mean_last_300s; });
  std::vector<double> lo, hi;
  for (std::size_t k = 0; k < e.mean.size(); ++k) {
    lo.push_back(e.mean[k] - e.sd[k]);
    hi.push_back(e.mean[k] + e.sd[k]);
  }
  auto f = figure(id, title,
                  "Robots inside D over " + std::to_string(e.runs.size()) + " seeds: mean, band mean ± sd, thin "
                  "lines the lowest and highest; dashed: the optimum λ*·|D| = " + fixed(optimum, 2) +
                  ". Final population " + fixed(final_pop.mean, 2) + " ± " + fixed(final_pop.sd, 2) + " (" +
                  fixed(final_pop.min, 0) + "–" + fixed(final_pop.max, 0) + "), mean of the last 300 s " +
                  fixed(last300.mean, 2) + " ± " + fixed(last300.sd, 2) + ".",
                  "simulated time [s]", "robots inside");
  f["y_min"] = 0.0;
  f["series"].push_back(band("mean ± sd", e.time, lo, hi));
  f["series"].push_back(series("mean", "line", e.time, e.mean));
  f["series"].push_back(series("lowest", "line", e.time, e.min));
  f["series"].push_back(series("highest", "line", e.time, e.max));
  f["series"].push_back(level("optimum λ*·|D|", 0.0, e.time.back(), optimum));
  f["series"][0]["color"] = "#2f7ed8";
  f["series"][1]["color"] = "#2f7ed8";
  f["series"][2]["color"] = "#94a3b8";
  f["series"][3]["color"] = "#94a3b8";
  f["series"][4]["color"] = "#2a9d4b";
  return f;
}

void drop_per_tick_files(const Ensemble& e) {
  for (const auto& run : e.runs) {
    for (const char* file : {"telemetry.csv", "chain.bin", "transitions.csv"}) {
      std::filesystem::remove(std::filesystem::path(run.dir) / file);
    }
  }
}

void write_population_rows(CsvWriter& csv, const Ensemble& e) {
  for (std::size_t k = 0; k < e.time.size(); ++k) {
    csv.row({e.name, e.time[k], e.mean[k], e.sd[k], e.min[k], e.max[k]});
  }
}

std::size_t stalled_seeds(const Ensemble& e) {
  return static_cast<std::size_t>(std::count_if(e.runs.begin(), e.runs.end(), [](const SeedRun& r) {
    return r.longest_retreat_under_way > stalled_retreat_after;
  }));
}

double pooled_J(const Ensemble& e, double C, bool last_half) {
  double output = 0.0, lambda = 0.0;
  for (const auto& r : e.runs) {
    const auto& s = last_half ? r.last_half : r.whole;
    output += s.output;
    lambda += s.lambda;
  }
  const double n = static_cast<double>(e.runs.size());
  return output > 0.0 ? C / (output / n) + lambda / n : std::numeric_limits<double>::infinity();
}

}  // namespace retreat::experiment
