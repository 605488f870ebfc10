// `retreat-experiment controllers`: every registered controller (retreat::agent::controller_names(),
// or the ones --controllers names) against `paper` on the same seeds and scenarios, each run by retreat-launch in one process:
// the finite queue (robotarium-2019.yaml) and the endless queue (steady-influx.yaml), physical
// world. Per run, from telemetry.csv (MODEL.md §4, with the measured output in place of T(λ)λ):
//   λ̄ = time-mean of the robots inside D / |D|,  output = deliveries / (|D| · span),
//   J = C / output + λ̄,  over the whole run and over its last half.
// Writes:
//   runs/<scenario>/<controller>/seed_<n>/   the launcher's run directories
//   seeds.csv      scenario, controller, seed, J and its parts over both spans, final, departed, lost
//   results.csv    one row per scenario and controller (the table's numbers)
//   results.md     the table in Markdown;  results.json;  population.csv;  report.html

#include <atomic>
#include <cmath>
#include <cstdio>
#include <future>
#include <limits>
#include <optional>
#include <thread>

#include "ensemble.hpp"
#include "page.hpp"
#include "retreat/experiment/prediction.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/model/optimum.hpp"
#include "retreat/model/population.hpp"
#include "retreat/scenario/scenario.hpp"
#include "retreat/experiment/subcommands.hpp"

namespace retreat::experiment {
namespace {

/// The endless queue's run in the reduced size (steady-influx.yaml runs an hour) [s].
constexpr double quick_endless = 1200.0;

/// The run length --quick gives case @p c in place of its scenario's, if it gives one [s].
std::optional<double> reduced_run(const ControllersOptions& o, const QueueCase& c) {
  if (o.common.quick && c.name == "endless") return quick_endless;
  return std::nullopt;
}

std::string pm(const Moments& m, int digits) {
  return std::isfinite(m.mean) ? fixed(m.mean, digits) + " ± " + fixed(m.sd, digits) : "∞ (a seed without deliveries)";
}

/// The run's tables, filled one ensemble (scenario, controller) at a time.
struct Tables {
  explicit Tables(const std::string& out)
      : per_seed(out + "/seeds.csv", {"scenario", "controller", "seed", "J_whole", "lambda_whole", "output_whole",
                                      "J_last_half", "lambda_last_half", "output_last_half", "final", "optimum",
                                      "departed", "lost", "retreating_at_end", "longest_retreat_under_way"}),
        results_csv(out + "/results.csv",
                    {"scenario", "controller", "seeds", "duration", "J_whole_pooled", "J_last_half_pooled",
                     "J_last_half_mean", "J_last_half_sd", "mean_population_last_half",
                     "predicted_population_last_half", "predicted_by_robot_population_last_half", "final_mean",
                     "final_sd",
                     "final_min", "final_max", "optimum", "departed_mean", "departed_min", "departed_max",
                     "deliveries_mean", "lost_total", "stalled_seeds"}),
        population(out + "/population.csv", {"ensemble", "time", "mean", "sd", "min", "max"}) {}
  CsvWriter per_seed, results_csv, population;
  nlohmann::json results = nlohmann::json::array(), rows = nlohmann::json::array(), figures = nlohmann::json::array();
  std::string markdown =
      "| scenario | controller | J whole run | J last half | J last half per seed | population last half | "
      "predicted (chain) | predicted (by robot) | final population | final min–max | optimum λ*·\\|D\\| | robots "
      "that left (min–max) | seeds with a stalled retreat |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::uint32_t by_robot_runs = 200;  ///< runs of the robot-by-robot chain (quick: 20)
  unsigned jobs = 1;                  ///< threads the robot-by-robot chain's runs are shared among
};

/// The model's predictions of one ensemble, for runs of `duration` simulated seconds: tabulate's
/// "predicted" columns.
struct Prediction {
  double duration = 0.0;
  std::optional<std::vector<double>> chain;  ///< predicted_population (rules whose chance is the count's alone)
  std::vector<double> by_robot;              ///< robot_by_robot_chain
};

Prediction predict(const scenario::Scenario& s, const std::string& controller, double duration,
                   std::uint32_t by_robot_runs, unsigned jobs) {
  return {duration, predicted_population(s, controller, duration),
          robot_by_robot_chain(s, controller, duration, by_robot_runs, jobs)};
}

/// Every ensemble's Prediction, worked out beside the runs. A prediction depends on the scenario,
/// the rule and the run's length, not on the runs, so one thread computes them from the start, in
/// the order tabulate asks for them, and fills the CPU the runs leave idle (a launch's last
/// seeds, the reading between launches). At normal priority: at the lowest (SCHED_IDLE) it
/// filled the same gaps, but on a machine busy with other work it got next to no CPU and the
/// table waited for minutes (a loaded test run timed out on it). Each number is the same as
/// computed in line (robot_by_robot_chain's sum is the same whatever thread ran which run).
class BackgroundPredictions {
 public:
  struct Task {
    scenario::Scenario scenario;
    std::string controller;
    double duration = 0.0;  ///< the scenario's run.duration (or the quick endless run's)
  };

  BackgroundPredictions(std::vector<Task> tasks, std::uint32_t by_robot_runs, unsigned jobs)
      : tasks_(std::move(tasks)), promises_(tasks_.size()) {
    for (auto& p : promises_) futures_.push_back(p.get_future());
    thread_ = std::thread([this, by_robot_runs, jobs] {
      for (std::size_t i = 0; i < tasks_.size() && !stop_; ++i) {
        try {
          promises_[i].set_value(predict(tasks_[i].scenario, tasks_[i].controller, tasks_[i].duration,
                                         by_robot_runs, jobs));
        } catch (...) {
          promises_[i].set_exception(std::current_exception());
        }
      }
    });
  }
  BackgroundPredictions(const BackgroundPredictions&) = delete;
  BackgroundPredictions& operator=(const BackgroundPredictions&) = delete;
  /// Stops after the prediction under way (a run that failed ends the experiment).
  ~BackgroundPredictions() {
    stop_ = true;
    thread_.join();
  }

  /// Task @p i's prediction, once it is ready.
  Prediction get(std::size_t i) { return futures_.at(i).get(); }

 private:
  std::vector<Task> tasks_;
  std::vector<std::promise<Prediction>> promises_;
  std::vector<std::future<Prediction>> futures_;
  std::atomic<bool> stop_{false};
  std::thread thread_;  // last: started once everything it uses exists
};

/// Every controller on `c`, one ensemble each (paper first).
std::vector<Ensemble> run_case(const ControllersOptions& o, const QueueCase& c, const SeedRange& seeds,
                               const std::vector<std::string>& controllers, double C) {
  std::vector<Ensemble> ensembles;
  for (const auto& name : controllers) {
    const std::string dir = o.common.out_dir + "/runs/" + c.name + "/" + name;
    LaunchRequest r{c.file, o.common.overrides, seeds, true, "", {}, dir, dir + ".log", o.common.jobs};
    r.overrides.push_back("agent.controller=" + name);
    if (const auto duration = reduced_run(o, c)) r.overrides.emplace_back("run.duration=" + fixed(*duration, 0));
    ensembles.push_back(run_ensemble(o.common.launcher, c.name + "-" + name, name, r, C));
  }
  return ensembles;
}

/// One ensemble's rows in every table, and its line on stderr. @p prediction was computed for the
/// run length the scenario gives; if the runs ended elsewhere it is computed again for theirs.
void tabulate(Tables& t, const QueueCase& c, const Ensemble& e, const scenario::Scenario& s, Prediction prediction) {
  const auto final_pop = over_seeds(e, [](const SeedRun& r) { return r.final_population; });
  const auto departed = over_seeds(e, [](const SeedRun& r) { return r.departed; });
  const auto deliveries = over_seeds(e, [](const SeedRun& r) { return r.whole.deliveries; });
  const auto j_half = over_seeds(e, [](const SeedRun& r) { return r.last_half.J; });
  const auto pop_half = over_seeds(e, [](const SeedRun& r) { return r.last_half.mean_population; });
  double lost = 0.0;  // agents the arena declared lost, all seeds
  for (const auto& r : e.runs) lost += r.agents_lost;
  const auto stalled = static_cast<double>(stalled_seeds(e));
  const double optimum = e.runs.front().optimal_population;
  const double jw = pooled_J(e, s.model.C, false), jh = pooled_J(e, s.model.C, true);
  const double duration = e.runs.front().duration;
  if (prediction.duration != duration) prediction = predict(s, e.label, duration, t.by_robot_runs, t.jobs);
  const auto& predicted = prediction.chain;
  const double predicted_half =
      predicted ? model::time_mean(*predicted, s.agent.dt, duration / 2.0, duration) : std::nan("");
  const double by_robot_half =
      model::time_mean(prediction.by_robot, s.agent.dt, duration / 2.0, duration);
  for (const auto& r : e.runs) {
    t.per_seed.row({c.name, e.label, r.seed, r.whole.J, r.whole.lambda, r.whole.output, r.last_half.J,
                    r.last_half.lambda, r.last_half.output, r.final_population, optimum, r.departed, r.agents_lost,
                    r.retreating_at_end, r.longest_retreat_under_way});
  }
  t.results_csv.row({c.name, e.label, e.runs.size(), e.runs.front().duration, jw, jh, j_half.mean, j_half.sd,
                     pop_half.mean, predicted_half, by_robot_half, final_pop.mean, final_pop.sd, final_pop.min, final_pop.max, optimum,
                     departed.mean, departed.min, departed.max, deliveries.mean, lost, stalled});
  t.results.push_back({{"scenario", c.name}, {"controller", e.label}, {"seeds", e.runs.size()},
                       {"duration", e.runs.front().duration}, {"J_whole_pooled", jw}, {"J_last_half_pooled", jh},
                       {"J_last_half", {{"mean", j_half.mean}, {"sd", j_half.sd}}},
                       {"mean_population_last_half", {{"mean", pop_half.mean}, {"sd", pop_half.sd}}},
                       {"predicted_population_last_half",
                        predicted ? nlohmann::json(predicted_half) : nlohmann::json(nullptr)},
                       {"predicted_by_robot_population_last_half", by_robot_half},
                       {"final_population", {{"mean", final_pop.mean}, {"sd", final_pop.sd}, {"min", final_pop.min},
                                             {"max", final_pop.max}}},
                       {"optimum", optimum}, {"J_at_optimum_ctmc", model::cost(s.model, model::lambda_star(s.model))},
                       {"departed", {{"mean", departed.mean}, {"min", departed.min}, {"max", departed.max}}},
                       {"deliveries_mean", deliveries.mean}, {"agents_lost_total", lost},
                       {"stalled_seeds", stalled}});
  const std::vector<std::string> cells = {
      c.name, e.label, fixed(jw, 3), fixed(jh, 3), pm(j_half, 3), pm(pop_half, 2),
      predicted ? fixed(predicted_half, 2) : std::string("—"), fixed(by_robot_half, 2), pm(final_pop, 2),
      fixed(final_pop.min, 0) + "–" + fixed(final_pop.max, 0), fixed(optimum, 2),
      fixed(departed.mean, 1) + " (" + fixed(departed.min, 0) + "–" + fixed(departed.max, 0) + ")",
      fixed(stalled, 0) + " of " + std::to_string(e.runs.size())};
  t.rows.push_back(cells);
  std::string line = "|";
  for (const auto& cell : cells) line += " " + cell + " |";
  t.markdown += line + "\n";
  write_population_rows(t.population, e);
  std::fprintf(stderr, "retreat-experiment: controllers: %s, %s: J %.3f (last half %.3f), final %.2f ± %.2f "
                       "(optimum %.2f), %.1f left\n", c.name.c_str(), e.label.c_str(), jw, jh, final_pop.mean,
               final_pop.sd, optimum, departed.mean);
}

/// The case's figures: the mean populations, and J per seed against paper (when any is finite).
void add_case_figures(nlohmann::json& figures, const QueueCase& c, const std::vector<Ensemble>& ensembles,
                      const SeedRange& seeds) {
  auto overlay = figure("population-" + c.name, "Mean population, " + c.label,
                        "Mean over " + std::to_string(seeds.count()) + " seeds (" + seeds.text() +
                            ") of the robots inside D, one line per controller; dashed: the optimum λ*·|D|.",
                        "simulated time [s]", "robots inside");
  overlay["y_min"] = 0.0;
  auto paired = figure("J-" + c.name, "J per seed against paper, " + c.label,
                       "Each point one seed: J over the last half of the run with paper (x) and with the controller "
                       "(y), same seed and scenario; below the diagonal the controller did better. Seeds without "
                       "deliveries (J = ∞) are left out.",
                       "J with paper [robots/m²]", "J with the controller [robots/m²]");
  const Ensemble& paper = ensembles.front();
  double j_lo = std::numeric_limits<double>::infinity(), j_hi = 0.0;
  for (const auto& e : ensembles) {
    overlay["series"].push_back(series(e.label, "line", e.time, e.mean));
    std::vector<double> x, y;
    for (std::size_t k = 0; k < e.runs.size() && k < paper.runs.size(); ++k) {
      if (!std::isfinite(paper.runs[k].last_half.J) || !std::isfinite(e.runs[k].last_half.J)) continue;
      x.push_back(paper.runs[k].last_half.J);
      y.push_back(e.runs[k].last_half.J);
      j_lo = std::min({j_lo, x.back(), y.back()});
      j_hi = std::max({j_hi, x.back(), y.back()});
    }
    paired["series"].push_back(series(e.label, "points", x, y));
  }
  overlay["series"].push_back(level("optimum λ*·|D|", 0.0, ensembles.front().time.back(),
                                    ensembles.front().runs.front().optimal_population));
  if (j_hi > 0.0) paired["series"].push_back(series("diagonal", "line", {j_lo, j_hi}, {j_lo, j_hi}, true));
  figures.push_back(overlay);
  if (j_hi > 0.0) figures.push_back(paired);
}

/// results.md: a note, then the table.
void write_markdown(const std::string& out, const SeedRange& seeds, const std::vector<std::string>& overrides,
                    std::uint32_t by_robot_runs, const std::string& markdown) {
  write_text(out + "/results.md", "Seeds " + seeds.text() + ", in-process, physical world" + with_overrides(overrides) + ". J = C/output + λ̄ (MODEL.md §4) from the measured "
        "population and deliveries; \"whole run\" and \"last half\" are J of the seeds pooled (mean output, mean λ̄) "
        "over [0, T] and [T/2, T]; \"per seed\" is the mean ± sd of each seed's J over [T/2, T]. Populations are "
        "robots inside D (mean ± sd over seeds); a run whose swarm emptied counts as empty until T. \"predicted "
        "(chain)\" is the population chain's mean over [T/2, T] (retreat::model::expected_population: each robot's "
        "chance averaged over a Poisson window count at the model's encounter rate; — for a rule with memory); \"by "
        "robot\" is the same chain run robot by robot (experiment::robot_by_robot_chain: Poisson onsets at the "
        "model's rate into each robot's own window and rule, " + std::to_string(by_robot_runs) + " runs). \"Seeds with a "
        "stalled retreat\" counts the seeds that ended with a robot still driving out after more than " +
        fixed(stalled_retreat_after, 0) + " s (summary.json's retreats.longest_under_way_seconds): robots jammed under the "
        "barrier certificates.\n\n" + markdown);
}

/// report.html.
void write_page(const std::string& out, const SeedRange& seeds, const std::vector<std::string>& overrides,
                const std::vector<std::string>& controllers, const Tables& t) {
  nlohmann::json table = {{"title", "Controllers on the same seeds"},
                          {"columns", {"scenario", "controller", "J whole run", "J last half", "J last half per seed",
                                       "population last half", "predicted (chain)", "predicted (by robot)",
                                       "final population",
                                       "final min–max", "optimum",
                                       "robots that left", "seeds with a stalled retreat"}},
                          {"rows", t.rows}};
  std::string names;
  for (const auto& n : controllers) names += (names.empty() ? "" : ", ") + n;
  nlohmann::json page = {
      {"title", "retreat experiment: controllers"},
      {"subtitle", "Every registered controller (" + names + ") on seeds " + seeds.text() + ", in-process" +
                       with_overrides(overrides)},
      {"sections", {{{"heading", "Cost and population"},
                     {"text", {"J = C/output + λ̄ (MODEL.md §4), with output = deliveries/(|D|·span) and λ̄ the "
                               "time-mean of the robots inside D over |D|; pooled over seeds for the whole run [0, T] "
                               "and its last half [T/2, T]. Lower is better."}},
                     {"figures", t.figures},
                     {"tables", {table}}}}},
      {"footer", "Written by retreat-experiment controllers; data in results.json, results.csv, results.md, seeds.csv, "
                 "population.csv."}};
  report::write_figures_page(page, out + "/report.html");
}

}  // namespace

int run_controllers(const ControllersOptions& o) {
  const auto cases = queue_cases(o.common);
  const SeedRange seeds = o.seeds.value_or(o.common.quick ? SeedRange{1, 3} : SeedRange{1, 100});
  const auto controllers = compared_controllers(o.common);
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;
  Tables t(out);
  if (o.common.quick) t.by_robot_runs = 20;
  t.jobs = worker_count(o.common.jobs);
  std::vector<scenario::Scenario> scenarios;
  std::vector<BackgroundPredictions::Task> tasks;  // case by case, controller by controller
  for (const auto& c : cases) {
    scenarios.push_back(scenario::load(c.file, o.common.overrides));
    const double duration = reduced_run(o, c).value_or(scenarios.back().run.duration);
    for (const auto& name : controllers) tasks.push_back({scenarios.back(), name, duration});
  }
  BackgroundPredictions predictions(std::move(tasks), t.by_robot_runs, t.jobs);
  std::size_t next_prediction = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& c = cases[k];
    const auto& s = scenarios[k];
    const auto ensembles = run_case(o, c, seeds, controllers, s.model.C);
    for (const auto& e : ensembles) tabulate(t, c, e, s, predictions.get(next_prediction++));
    add_case_figures(t.figures, c, ensembles, seeds);
  }
  t.per_seed.close();
  t.results_csv.close();
  t.population.close();
  write_json(out + "/results.json", t.results);
  write_markdown(out, seeds, o.common.overrides, t.by_robot_runs, t.markdown);
  write_page(out, seeds, o.common.overrides, controllers, t);
  std::fprintf(stderr, "retreat-experiment: controllers: %s/results.md, %s/report.html\n", out.c_str(), out.c_str());
  return 0;
}

}  // namespace retreat::experiment
