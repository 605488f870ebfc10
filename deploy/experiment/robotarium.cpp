// `retreat-experiment robotarium`: the paper's Robotarium experiment (MODEL.md §6) over many
// seeds, each run by retreat-launch: the physical world with real agent processes over DDS, the
// same in one process, the same with an endless queue (steady-influx.yaml), and the kinetic
// world. Writes:
//   <set-up>/seed_<n>/     the launcher's run directories (telemetry.csv, summary.json, ...)
//   population.csv         ensemble, time, mean, sd, min, max (robots inside, over seeds)
//   seeds.csv              ensemble, seed, final, mean_last_300s, mean_last_half, departed, deliveries, lost
//   results.json           per set-up: final population and last-300-s mean (mean, sd, min, max)
//   report.html

#include <algorithm>
#include <cstdio>
#include <optional>

#include "ensemble.hpp"
#include "page.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/experiment/subcommands.hpp"

namespace retreat::experiment {
namespace {

nlohmann::json moments_json(const Moments& m) {
  return {{"mean", m.mean}, {"sd", m.sd}, {"se", m.se}, {"min", m.min}, {"max", m.max}, {"n", m.n}};
}

struct Part {
  std::string name, label;
  LaunchRequest request;
};

/// The set-ups: agent processes (unless --no-processes), then in-process on the finite queue, the
/// endless queue and the kinetic world.
std::vector<Part> plan_parts(const RobotariumOptions& o, const std::string& finite, const std::string& endless) {
  const SeedRange seeds = o.seeds.value_or(o.common.quick ? SeedRange{1, 3} : SeedRange{1, 100});
  const SeedRange process_seeds = o.process_seeds.value_or(o.common.quick ? SeedRange{1, 2} : SeedRange{1, 5});
  std::optional<double> process_duration = o.process_duration;
  if (!process_duration && o.common.quick) process_duration = 150.0;
  const std::string& out = o.common.out_dir;
  std::vector<Part> parts;
  if (!o.no_processes) {
    LaunchRequest r{finite, {}, process_seeds, false, o.dds, o.domain, out + "/processes", out + "/processes.log"};
    if (process_duration) r.overrides.push_back("run.duration=" + fixed(*process_duration, 3));
    parts.push_back({"processes", "finite queue, physical world, agent processes over " + o.dds, r});
  }
  parts.push_back({"finite-in-process", "finite queue, physical world, in-process",
                   {finite, {}, seeds, true, "", {}, out + "/finite-in-process", out + "/finite-in-process.log"}});
  parts.push_back({"endless-in-process", "endless queue, physical world, in-process",
                   {endless, {}, seeds, true, "", {}, out + "/endless-in-process", out + "/endless-in-process.log"}});
  parts.push_back({"kinetic-in-process", "finite queue, kinetic world, in-process",
                   {finite, {"arena.encounter_model=kinetic"}, seeds, true, "", {}, out + "/kinetic-in-process",
                    out + "/kinetic-in-process.log"}});
  for (auto& p : parts) {
    if (p.request.in_process) p.request.jobs = o.common.jobs;
  }
  return parts;
}

/// What the ensembles come to: results.json's content, the figures and the table's rows.
struct Summary {
  nlohmann::json results = nlohmann::json::object();
  nlohmann::json figures = nlohmann::json::array(), rows = nlohmann::json::array();
  std::vector<nlohmann::json> mean_series;
};

/// Writes population.csv and seeds.csv; returns the summary of every ensemble.
Summary tabulate(const std::string& out, const std::vector<Ensemble>& ensembles) {
  CsvWriter population(out + "/population.csv", {"ensemble", "time", "mean", "sd", "min", "max"});
  CsvWriter per_seed(out + "/seeds.csv", {"ensemble", "seed", "final", "mean_last_300s", "mean_last_half", "departed",
                                          "deliveries", "lost"});
  Summary m;
  for (const auto& e : ensembles) {
    write_population_rows(population, e);
    for (const auto& r : e.runs) {
      per_seed.row({e.name, r.seed, r.final_population, r.mean_last_300s, r.last_half.mean_population, r.departed,
                    r.whole.deliveries, r.agents_lost});
    }
    const auto final_pop = over_seeds(e, [](const SeedRun& r) { return r.final_population; });
    const auto last300 = over_seeds(e, [](const SeedRun& r) { return r.mean_last_300s; });
    const auto departed = over_seeds(e, [](const SeedRun& r) { return r.departed; });
    const auto lost = over_seeds(e, [](const SeedRun& r) { return static_cast<double>(r.agents_lost); });
    const double optimum = e.runs.front().optimal_population;
    m.results[e.name] = {{"label", e.label}, {"seeds", e.runs.size()}, {"duration", e.runs.front().duration},
                         {"optimal_population", optimum}, {"population_final", moments_json(final_pop)},
                         {"population_mean_last_300s", moments_json(last300)}, {"departed", moments_json(departed)},
                         {"agents_lost", moments_json(lost)}};
    m.rows.push_back({e.label, e.runs.size(), fixed(e.runs.front().duration, 0),
                      fixed(final_pop.mean, 2) + " ± " + fixed(final_pop.sd, 2),
                      fixed(final_pop.min, 0) + "–" + fixed(final_pop.max, 0),
                      fixed(last300.mean, 2) + " ± " + fixed(last300.sd, 2), fixed(optimum, 2),
                      fixed(departed.mean, 1), fixed(lost.mean, 1)});
    m.figures.push_back(population_figure(e, "population-" + e.name, "Population: " + e.label));
    m.mean_series.push_back(series(e.label, "line", e.time, e.mean));
  }
  population.close();
  per_seed.close();
  return m;
}

/// Lockstep runs are bit-for-bit determined by scenario and seed, whatever carries the
/// messages: the process runs (ensembles[0]) must repeat the in-process runs (ensembles[1]) of
/// the same seeds. Records the comparison in `results`; returns the sentence for the report.
std::string compare_trajectories(const std::vector<Ensemble>& ensembles, nlohmann::json& results) {
  std::size_t same = 0, both = 0;
  bool same_duration = ensembles[0].runs.front().duration == ensembles[1].runs.front().duration;
  for (const auto& p : ensembles[0].runs) {
    for (const auto& q : ensembles[1].runs) {
      if (p.seed != q.seed) continue;
      ++both;
      same += p.trajectory_sha256 == q.trajectory_sha256 ? 1 : 0;
    }
  }
  results["processes"]["same_trajectory_as_in_process"] = {{"seeds_in_both", both}, {"identical", same},
                                                           {"same_duration", same_duration}};
  return same_duration ? "Trajectory hashes of the agent-process runs equal those of the in-process runs for " +
                             std::to_string(same) + " of the " + std::to_string(both) + " seeds run both ways."
                       : "The agent-process runs are shorter (--process-duration) than the in-process ones, so "
                         "their trajectory hashes differ by construction.";
}

/// report.html.
void write_page(const std::string& out, const scenario::Scenario& s, const std::vector<Ensemble>& ensembles,
                Summary& m, const std::string& identity) {
  auto overlay = figure("population-means", "Mean population of every set-up",
                        "Mean over seeds of the robots inside D; dashed: the optimum λ*·|D|.", "simulated time [s]",
                        "robots inside");
  overlay["y_min"] = 0.0;
  double t_end = 0.0;
  for (auto& mean : m.mean_series) {
    t_end = std::max(t_end, mean["x"].back().get<double>());
    overlay["series"].push_back(std::move(mean));
  }
  overlay["series"].push_back(level("optimum λ*·|D|", 0.0, t_end, ensembles.front().runs.front().optimal_population));
  m.figures.push_back(overlay);
  nlohmann::json table = {{"title", "Populations over seeds"},
                          {"columns", {"set-up", "seeds", "duration [s]", "final (mean ± sd)", "final min–max",
                                       "mean of the last 300 s", "optimum λ*·|D|", "robots that left", "agents lost"}},
                          {"rows", m.rows}};
  nlohmann::json text = {"Each set-up is run by retreat-launch, one run directory per seed beside this report. "
                         "Agent processes: every robot's agent is its own process and DDS participant."};
  if (!identity.empty()) text.push_back(identity);
  nlohmann::json page = {
      {"title", "retreat experiment: the Robotarium experiment"},
      {"subtitle", "MODEL.md §6: ellipse 1.2 × 0.8 m, 8 robots inside, 4 waiting (finite) or an endless queue; "
                   "controller " + s.agent.controller},
      {"sections", {{{"heading", "Population against the optimum"},
                     {"text", text},
                     {"figures", m.figures},
                     {"tables", {table}}}}},
      {"footer", "Written by retreat-experiment robotarium; data in results.json, population.csv, seeds.csv."}};
  report::write_figures_page(page, out + "/report.html");
}

void print_summary(const std::string& out, const std::vector<Ensemble>& ensembles) {
  for (const auto& e : ensembles) {
    const auto last300 = over_seeds(e, [](const SeedRun& r) { return r.mean_last_300s; });
    const auto final_pop = over_seeds(e, [](const SeedRun& r) { return r.final_population; });
    std::fprintf(stderr, "retreat-experiment: robotarium: %s, %zu seeds: final %.2f ± %.2f, last 300 s %.2f ± %.2f "
                         "(optimum %.2f)\n", e.label.c_str(), e.runs.size(), final_pop.mean, final_pop.sd, last300.mean,
                 last300.sd, e.runs.front().optimal_population);
  }
  std::fprintf(stderr, "retreat-experiment: robotarium: %s/report.html\n", out.c_str());
}

}  // namespace

int run_robotarium(const RobotariumOptions& o) {
  const auto finite = scenario_file(o.common, "robotarium-2019.yaml");
  const auto endless = scenario_file(o.common, "steady-influx.yaml");
  const auto s = scenario::load(finite);
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;
  std::vector<Ensemble> ensembles;
  for (const auto& p : plan_parts(o, finite, endless)) {
    ensembles.push_back(run_ensemble(o.common.launcher, p.name, p.label, p.request, s.model.C));
  }
  auto summary = tabulate(out, ensembles);
  const std::string identity = o.no_processes ? std::string() : compare_trajectories(ensembles, summary.results);
  write_json(out + "/results.json", summary.results);
  write_page(out, s, ensembles, summary, identity);
  print_summary(out, ensembles);
  return 0;
}

}  // namespace retreat::experiment
