// `retreat-experiment sweep`: every registered rule (or `paper` and the ones --controllers names)
// on a grid of 18 scenarios around the two shipped ones (robotarium-2019.yaml, finite queue;
// steady-influx.yaml, endless queue): shape, |D| from 2 to 20 m², L, λ_in, K_p, a start below
// the optimum, both queues and both worlds.
// Per cell and rule, over the last half of the run: the population's mean over seeds against
// the optimum λ*·|D| as |mean − N*|/N*, and J (pooled over seeds) relative to `paper`'s.
// Writes:
//   runs/<cell>/<rule>/   the launcher's run directories, each seed's summary.json (the per-tick
//                         files are removed once read)
//   results.csv, results.json, results.md, report.html (the two heat maps and the tables)

#include <cmath>
#include <cstdio>

#include "ensemble.hpp"
#include "page.hpp"
#include "retreat/experiment/subcommands.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::experiment {
namespace {

/// An endless queue's run in the reduced size [s].
constexpr double quick_duration = 300.0;

/// One scenario of the grid.
struct Cell {
  std::string name;
  bool endless = false;                ///< steady-influx.yaml, else robotarium-2019.yaml
  std::vector<std::string> overrides;  ///< --set on top of the shipped scenario
  std::string unreachable;             ///< why no one-sided rule can reach N* here (empty: it can)
};

/// The grid. Each cell changes one thing (or one geometry) from a shipped scenario; the robots
/// inside at the start are scaled with |D| so that the swarm starts above the optimum, except
/// in the two cells that start below it.
const std::vector<Cell>& cells() {
  static const std::vector<Cell> all = {
      {"finite", false, {}, ""},
      {"finite-kinetic", false, {"arena.encounter_model=kinetic"}, ""},
      {"finite-rectangle-3", false, {"arena.shape=rectangle", "arena.width=2.0", "arena.height=1.5"}, ""},
      {"finite-ellipse-2", false,
       {"arena.semi_axis_x=0.9772", "arena.semi_axis_y=0.6515", "arena.robots_inside=6", "arena.robots_waiting=2"}, ""},
      {"finite-rectangle-6.4", false,
       {"arena.shape=rectangle", "arena.width=3.2", "arena.height=2.0", "arena.robots_inside=16",
        "arena.robots_waiting=4"},
       ""},
      {"finite-rectangle-20", false,
       {"arena.encounter_model=kinetic", "arena.shape=rectangle", "arena.width=5.0", "arena.height=4.0",
        "arena.robots_inside=50", "arena.robots_waiting=10"},
       ""},
      {"finite-L45", false, {"agent.L=45"}, ""},
      {"finite-L180", false, {"agent.L=180"}, ""},
      {"finite-Kp-0.1", false, {"agent.K_p=0.1"}, ""},
      {"finite-below", false, {"arena.robots_inside=3", "arena.robots_waiting=0"},
       "3 robots and nobody arriving: below N* = 4.55, and robots can only leave"},
      {"endless", true, {}, ""},
      {"endless-kinetic", true, {"arena.encounter_model=kinetic"}, ""},
      {"endless-lambda-0.01", true, {"arena.encounter_model=kinetic", "agent.lambda_in=0.01"}, ""},
      {"endless-lambda-0.04", true, {"arena.encounter_model=kinetic", "agent.lambda_in=0.04"}, ""},
      {"endless-rectangle-10", true,
       {"arena.encounter_model=kinetic", "arena.shape=rectangle", "arena.width=4.0", "arena.height=2.5",
        "arena.robots_inside=20"},
       ""},
      {"endless-below", true, {"arena.encounter_model=kinetic", "arena.robots_inside=1"}, ""},
      {"endless-Kp-0.01", true, {"arena.encounter_model=kinetic", "agent.K_p=0.01"}, ""},
      {"endless-L180", true, {"arena.encounter_model=kinetic", "agent.L=180"}, ""},
  };
  return all;
}

struct Result {
  double mean = 0.0, sd = 0.0, optimum = 0.0, J = 0.0;
  double error = 0.0;       ///< |mean − N*|/N*
  double relative_J = 0.0;  ///< J over paper's in the same cell
  std::size_t stalled = 0;  ///< seeds that ended with a stalled retreat (stalled_seeds)
};


}  // namespace

int run_sweep(const SweepOptions& o) {
  const SeedRange seeds = o.seeds.value_or(o.common.quick ? SeedRange{1, 2} : SeedRange{1, 100});
  const auto rules = compared_controllers(o.common);
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;
  const auto queues = queue_cases(o.common);  // the finite queue, then the endless one

  // results[cell][rule]
  std::vector<std::vector<Result>> results;
  CsvWriter csv(out + "/results.csv", {"cell", "queue", "controller", "seeds", "optimum", "mean_population_last_half",
                                       "sd_population_last_half", "relative_error", "J_last_half_pooled",
                                       "J_relative_to_paper", "reachable", "stalled_seeds"});
  nlohmann::json json_rows = nlohmann::json::array();
  for (const auto& cell : cells()) {
    const std::string& file = queues[cell.endless ? 1 : 0].file;
    // The cell's values after the user's --set: a cell is what the sweep varies.
    auto overrides = o.common.overrides;
    overrides.insert(overrides.end(), cell.overrides.begin(), cell.overrides.end());
    if (o.common.quick) overrides.push_back("run.duration=" + fixed(quick_duration, 0));
    // C for J: the scenario with the cell's overrides (C itself is never swept).
    const double C = scenario::load(file, overrides).model.C;
    std::vector<Result> row;
    for (const auto& rule : rules) {
      const std::string dir = out + "/runs/" + cell.name + "/" + rule;
      LaunchRequest r{file, overrides, seeds, true, "", {}, dir, dir + ".log", o.common.jobs};
      r.overrides.push_back("agent.controller=" + rule);
      const auto e = run_ensemble(o.common.launcher, cell.name + "-" + rule, rule, r, C);
      const auto population = over_seeds(e, [](const SeedRun& x) { return x.last_half.mean_population; });
      row.push_back({population.mean, population.sd, e.runs.front().optimal_population, pooled_J(e, C, true),
                     0.0, 0.0, stalled_seeds(e)});
      drop_per_tick_files(e);
      std::fprintf(stderr, "retreat-experiment: sweep: %s, %s: last half %.2f ± %.2f (optimum %.2f)\n",
                   cell.name.c_str(), rule.c_str(), population.mean, population.sd, row.back().optimum);
    }
    for (std::size_t k = 0; k < rules.size(); ++k) {
      auto& x = row[k];
      x.error = std::abs(x.mean - x.optimum) / x.optimum;
      x.relative_J = x.J / row.front().J;  // rules[0] is paper
      csv.row({cell.name, cell.endless ? "endless" : "finite", rules[k], seeds.count(), x.optimum, x.mean, x.sd,
               x.error, x.J, x.relative_J, cell.unreachable.empty() ? 1 : 0, x.stalled});
      json_rows.push_back({{"cell", cell.name}, {"queue", cell.endless ? "endless" : "finite"},
                           {"overrides", cell.overrides}, {"controller", rules[k]}, {"optimum", x.optimum},
                           {"population_last_half", {{"mean", x.mean}, {"sd", x.sd}}},
                           {"relative_error", x.error}, {"J_last_half_pooled", finite_or_null(x.J)},
                           {"J_relative_to_paper", finite_or_null(x.relative_J)},
                           {"unreachable", cell.unreachable}, {"stalled_seeds", x.stalled}});
    }
    results.push_back(std::move(row));
  }
  csv.close();
  write_json(out + "/results.json", json_rows);

  // The heat maps and the Markdown tables: a cell per row, a rule per column.
  std::vector<std::string> row_labels;
  for (const auto& c : cells()) row_labels.push_back(c.name + (c.unreachable.empty() ? "" : " (unreachable)"));
  nlohmann::json error_values = nlohmann::json::array(), error_text = nlohmann::json::array();
  nlohmann::json j_values = nlohmann::json::array(), j_text = nlohmann::json::array();
  std::string md_error = "| cell | N* |", md_j = "| cell |";
  for (const auto& rule : rules) {
    md_error += " " + rule + " |";
    md_j += " " + rule + " |";
  }
  md_error += "\n|---|---|";
  md_j += "\n|---|";
  for (std::size_t k = 0; k < rules.size(); ++k) {
    md_error += "---|";
    md_j += "---|";
  }
  md_error += "\n";
  md_j += "\n";
  for (std::size_t i = 0; i < cells().size(); ++i) {
    nlohmann::json ev = nlohmann::json::array(), et = nlohmann::json::array(), jv = nlohmann::json::array(),
                   jt = nlohmann::json::array();
    md_error += "| " + row_labels[i] + " | " + fixed(results[i].front().optimum, 2) + " |";
    md_j += "| " + row_labels[i] + " |";
    for (std::size_t k = 0; k < rules.size(); ++k) {
      const auto& x = results[i][k];
      ev.push_back(round6(x.error));
      const std::string cell_text = fixed(x.mean, 2) + "\u00a0(" + fixed(100.0 * x.error, 0) + "\u00a0%)";  // no wrap
      et.push_back(cell_text);
      const bool finite_J = std::isfinite(x.relative_J);
      jv.push_back(finite_or_null(round6(x.relative_J)));
      jt.push_back(finite_J ? fixed(x.relative_J, 3) : std::string("–"));
      md_error += " " + cell_text + " |";
      md_j += " " + (finite_J ? fixed(x.relative_J, 3) : std::string("– (no deliveries)")) + " |";
    }
    md_error += "\n";
    md_j += "\n";
    error_values.push_back(ev);
    error_text.push_back(et);
    j_values.push_back(jv);
    j_text.push_back(jt);
  }
  // A heat map of one table: a cell per row, a rule per column.
  const auto heatmap = [&](const std::string& id, const std::string& title, const std::string& note,
                           const nlohmann::json& values, const nlohmann::json& text, double low, double high) {
    auto f = figure(id, title, note, "rule", "scenario");
    f.erase("series");
    f["heatmap"] = {{"rows", row_labels}, {"columns", rules}, {"values", values}, {"text", text},
                    {"low", low},         {"high", high}};
    return f;
  };
  const nlohmann::json figures = {
      heatmap("error", "Distance to the optimum over the last half",
              "Each cell: the mean over seeds " + seeds.text() +
                  " of the robots inside D over the last half, and |mean − N*|/N*; green within 10 %, red at 50 % "
                  "and more.",
              error_values, error_text, 0.0, 0.5),
      heatmap("J-relative", "J over the last half, relative to paper",
              "Each cell: J (pooled over seeds) of the rule over paper's on the same seeds; below 1 the rule does "
              "better. –: a J without deliveries.",
              j_values, j_text, 0.8, 1.2)};
  write_text(out + "/results.md", "Seeds " + seeds.text() + ", in-process" + with_overrides(o.common.overrides) +
                                      ". Population over the last half (mean over seeds) and "
                                      "|mean − N*|/N*:\n\n" +
                                      md_error + "\nJ over the last half (pooled over seeds) relative to paper's:\n\n" +
                                      md_j);
  nlohmann::json page = {
      {"title", "retreat experiment: sweep"},
      {"subtitle", "Every registered rule on " + std::to_string(cells().size()) + " scenarios, seeds " + seeds.text() +
                       ", in-process" + with_overrides(o.common.overrides)},
      {"sections", {{{"heading", "Where each rule lands against the optimum"},
                     {"text", {"Cells around the shipped robotarium-2019 (finite queue) and steady-influx (endless "
                               "queue) scenarios; each changes one thing (results.json lists the overrides)."}},
                     {"figures", figures}}}},
      {"footer", "Written by retreat-experiment sweep; data in results.json, results.csv, results.md."}};
  report::write_figures_page(page, out + "/report.html");
  std::fprintf(stderr, "retreat-experiment: sweep: %s/results.md, %s/report.html\n", out.c_str(), out.c_str());
  return 0;
}

}  // namespace retreat::experiment
