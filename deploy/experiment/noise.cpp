// `retreat-experiment noise`: how each registered rule (or `paper` and the ones --controllers
// names) degrades when the robots' proximity sensors miss onsets or report false ones
// (arena.missed_onsets, arena.false_onsets), on the finite queue (robotarium-2019.yaml) and the
// endless queue (steady-influx.yaml), kinetic world (the noise is the sensor's, not the world's;
// the kinetic world makes the 94 ensembles affordable). Beside every rule, the three rules that
// can correct for a known sensor (confident-proportional, influx-matching, adaptive-proportional)
// run once more told the true rates (agent.missed_onsets, agent.false_onsets). Per ensemble: the
// population over the last half (mean ± sd over seeds) and J over the last half, pooled.
// Writes:
//   runs/<scenario>/<noise>/<rule>/          the launcher's run directories, each seed's
//                                            summary.json (the per-tick files, telemetry.csv,
//                                            chain.bin and transitions.csv, are removed once
//                                            read: all of them would take about 25 GB)
//   results.csv, results.json, results.md, report.html

#include <cmath>
#include <cstdio>

#include "ensemble.hpp"
#include "page.hpp"
#include "retreat/agent/controller_registry.hpp"
#include "retreat/experiment/subcommands.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::experiment {
namespace {

/// The endless queue's run in the reduced size [s].
constexpr double quick_endless = 300.0;

/// One sensor: the chance of missing an onset and the rate of false ones [1/s].
struct Noise {
  std::string name;
  double missed = 0.0;
  double false_rate = 0.0;
};

/// The sensors compared: each kind of error alone, at two levels, against the perfect one. At the
/// optimum a robot meets about 0.06 others per second, so 0.02 and 0.05 false onsets per second
/// add a third and four fifths to its count, and 20 % and 40 % misses take a fifth and two fifths.
const std::vector<Noise>& noises() {
  static const std::vector<Noise> all = {{"perfect", 0.0, 0.0},
                                         {"missed-0.2", 0.2, 0.0},
                                         {"missed-0.4", 0.4, 0.0},
                                         {"false-0.02", 0.0, 0.02},
                                         {"false-0.05", 0.0, 0.05}};
  return all;
}

/// The rules that correct their estimate for a known sensor (Controller::corrects_sensor).
bool corrects(const std::string& rule) { return agent::make_controller(rule)->corrects_sensor(); }

struct Row {
  std::string scenario, noise, rule;
  bool corrected = false;
  double missed = 0.0, false_rate = 0.0;
  Moments population;
  double J = 0.0, optimum = 0.0;
};

}  // namespace

int run_noise(const NoiseOptions& o) {
  const auto cases = queue_cases(o.common);
  const SeedRange seeds = o.seeds.value_or(o.common.quick ? SeedRange{1, 2} : SeedRange{1, 100});
  const auto rules = compared_controllers(o.common);
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;

  std::vector<Row> rows;
  for (const auto& c : cases) {
    const auto s = scenario::load(c.file, o.common.overrides);
    for (const auto& noise : noises()) {
      for (const auto& rule : rules) {
        for (const bool corrected : {false, true}) {
          if (corrected && (!corrects(rule) || noise.name == "perfect")) continue;
          const std::string label = rule + (corrected ? " corrected" : "");
          const std::string dir = out + "/runs/" + c.name + "/" + noise.name + "/" + rule + (corrected ? "-corrected" : "");
          LaunchRequest r{c.file, o.common.overrides, seeds, true, "", {}, dir, dir + ".log", o.common.jobs};
          r.overrides.insert(r.overrides.end(),
                             {"agent.controller=" + rule, "arena.encounter_model=kinetic",
                              "arena.missed_onsets=" + fixed(noise.missed, 2),
                              "arena.false_onsets=" + fixed(noise.false_rate, 2)});
          if (corrected) {
            r.overrides.push_back("agent.missed_onsets=" + fixed(noise.missed, 2));
            r.overrides.push_back("agent.false_onsets=" + fixed(noise.false_rate, 2));
          }
          if (o.common.quick && c.name == "endless") r.overrides.push_back("run.duration=" + fixed(quick_endless, 0));
          const auto e = run_ensemble(o.common.launcher, c.name + "-" + noise.name + "-" + label, label, r, s.model.C);
          Row row{c.name, noise.name, rule, corrected, noise.missed, noise.false_rate,
                  over_seeds(e, [](const SeedRun& x) { return x.last_half.mean_population; }),
                  pooled_J(e, s.model.C, true), e.runs.front().optimal_population};
          drop_per_tick_files(e);
          std::fprintf(stderr, "retreat-experiment: noise: %s, %s, %s: last half %.2f ± %.2f (optimum %.2f)\n",
                       c.name.c_str(), noise.name.c_str(), label.c_str(), row.population.mean, row.population.sd,
                       row.optimum);
          rows.push_back(row);
        }
      }
    }
  }

  CsvWriter csv(out + "/results.csv", {"scenario", "noise", "missed_onsets", "false_onsets", "controller", "corrected",
                                       "seeds", "mean_population_last_half", "sd_population_last_half",
                                       "J_last_half_pooled", "optimum"});
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : rows) {
    csv.row({r.scenario, r.noise, r.missed, r.false_rate, r.rule, r.corrected ? 1 : 0, seeds.count(), r.population.mean,
             r.population.sd, r.J, r.optimum});
    results.push_back({{"scenario", r.scenario}, {"noise", r.noise}, {"missed_onsets", r.missed},
                       {"false_onsets", r.false_rate}, {"controller", r.rule}, {"corrected", r.corrected},
                       {"population_last_half", {{"mean", r.population.mean}, {"sd", r.population.sd}}},
                       {"J_last_half_pooled", finite_or_null(r.J)}, {"optimum", r.optimum}});
  }
  csv.close();
  write_json(out + "/results.json", results);

  // results.md and the page's tables: per scenario, a rule per row and a sensor per column.
  std::string md = "Seeds " + seeds.text() + ", in-process, kinetic world" + with_overrides(o.common.overrides) +
                   ". Each cell: the mean over seeds of the robots inside D over the last "
                   "half of the run (± sd over seeds). \"corrected\": the rule told the sensor's true rates.\n";
  nlohmann::json tables = nlohmann::json::array(), figures = nlohmann::json::array();
  for (const auto& c : cases) {
    std::vector<std::string> columns = {"rule"};
    for (const auto& n : noises()) columns.push_back(n.name);
    md += "\n" + c.label + ", optimum " + fixed(rows.front().optimum, 2) + ":\n\n|";
    for (const auto& col : columns) md += " " + col + " |";
    md += "\n|";
    for (std::size_t k = 0; k < columns.size(); ++k) md += "---|";
    md += "\n";
    nlohmann::json table_rows = nlohmann::json::array();
    std::vector<std::string> labels;
    for (const auto& r : rows) {
      const std::string label = r.rule + (r.corrected ? " corrected" : "");
      if (r.scenario == c.name && std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
    }
    for (const auto& label : labels) {
      std::vector<std::string> cells = {label};
      for (const auto& n : noises()) {
        std::string cell = "–";
        for (const auto& r : rows) {
          if (r.scenario == c.name && r.noise == n.name && r.rule + (r.corrected ? " corrected" : "") == label) {
            cell = fixed(r.population.mean, 2) + " ± " + fixed(r.population.sd, 2);
          }
        }
        cells.push_back(cell);
      }
      std::string line = "|";
      for (const auto& cell : cells) line += " " + cell + " |";
      md += line + "\n";
      table_rows.push_back(cells);
    }
    tables.push_back({{"title", c.label}, {"columns", columns}, {"rows", table_rows}});
    // Two figures per scenario: the population against each kind of error.
    for (const bool missed_axis : {true, false}) {
      auto f = figure(std::string("population-") + c.name + (missed_axis ? "-missed" : "-false"),
                      std::string("Population over the last half, ") + c.label + ", " +
                          (missed_axis ? "missed onsets" : "false onsets"),
                      "Mean over seeds " + seeds.text() + " (kinetic world), one line per rule; dashed: the optimum.",
                      missed_axis ? "chance of missing an onset" : "false onsets per second",
                      "robots inside, last half");
      for (const auto& label : labels) {
        std::vector<double> x, y;
        for (const auto& n : noises()) {
          const bool on_axis = missed_axis ? n.false_rate == 0.0 : n.missed == 0.0;
          if (!on_axis) continue;
          for (const auto& r : rows) {
            if (r.scenario == c.name && r.noise == n.name && r.rule + (r.corrected ? " corrected" : "") == label) {
              x.push_back(missed_axis ? n.missed : n.false_rate);
              y.push_back(r.population.mean);
            }
          }
        }
        if (!x.empty()) f["series"].push_back(series(label, "line", x, y));
      }
      f["y_min"] = 0.0;
      const double x_max = missed_axis ? 0.4 : 0.05;
      f["series"].push_back(level("optimum λ*·|D|", 0.0, x_max, rows.front().optimum));
      figures.push_back(f);
    }
  }
  write_text(out + "/results.md", md);
  nlohmann::json page = {
      {"title", "retreat experiment: sensing noise"},
      {"subtitle", "Every registered rule with missed and false onsets, seeds " + seeds.text() +
                       ", in-process, kinetic world" + with_overrides(o.common.overrides)},
      {"sections", {{{"heading", "Population over the last half"},
                     {"text", {"Each rule on robots whose sensors miss each encounter onset with a chance "
                               "(arena.missed_onsets) or report false onsets at a rate (arena.false_onsets). "
                               "\"corrected\": the rule is told the true rates (agent.missed_onsets, "
                               "agent.false_onsets) and corrects its estimate."}},
                     {"figures", figures},
                     {"tables", tables}}}},
      {"footer", "Written by retreat-experiment noise; data in results.json, results.csv, results.md."}};
  report::write_figures_page(page, out + "/report.html");
  std::fprintf(stderr, "retreat-experiment: noise: %s/results.md, %s/report.html\n", out.c_str(), out.c_str());
  return 0;
}

}  // namespace retreat::experiment
