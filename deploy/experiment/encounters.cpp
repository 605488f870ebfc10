// `retreat-experiment encounters`: the paper's encounter-model validation (MODEL.md §2, §6) in
// the physical world of retreat::physics, set up by deploy/scenarios/validation-encounters.yaml
// (λ = 0.99, δ = 0.11, v = 1, barrier certificates). Writes:
//   intervals.csv   robot, onset time, time since that robot's previous onset [s]
//   contacts.csv    kind (robot: a robot's contact episode; pair), robot, other, start, end, duration
//   histograms.csv  kind, bin centre, measured density, model density, fitted density
//   results.json    rates, fitted ρ and the fits' quality;   report.html

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "launch.hpp"
#include "page.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/physics/world.hpp"
#include "retreat/scenario/scenario.hpp"
#include "stats.hpp"
#include "retreat/experiment/subcommands.hpp"

namespace retreat::experiment {
namespace {

constexpr double warm_up = 5.0;  // s: lets the placement's correlations wash out (as the unit test)
constexpr double paper_rho = 2.44;  // the paper's fitted resolution rate [1/s]
constexpr int bins = 40;

/// Kolmogorov–Smirnov critical value at α = 0.05 for a fully specified distribution:
/// 1.358/√n (asymptotic). For exponentials with a fitted rate (Stephens 1974, Table 1A):
/// (D − 0.2/n)(√n + 0.26 + 0.5/√n) ≤ 1.094.
double ks_critical_specified(double n) { return 1.358 / std::sqrt(n); }
double ks_critical_fitted(double n) { return 1.094 / (std::sqrt(n) + 0.26 + 0.5 / std::sqrt(n)) + 0.2 / n; }

/// The world of one run: the scenario resized to `robots` at the file's density.
struct Setup {
  scenario::Scenario s;
  std::uint32_t robots = 0;
  double side = 0.0;      ///< of the square [m]
  double duration = 0.0;  ///< measured [s]
};

/// What the simulation measured (the CSV files of the raw data are written as it runs).
struct Measured {
  std::vector<double> intervals, robot_durations, pair_durations;
  double onsets = 0.0;
};

/// The fitted rates and their Kolmogorov–Smirnov checks (MODEL.md §6).
struct Fit {
  double onsets = 0.0, area = 0.0, lambda = 0.0;
  double omega_paper = 0.0, omega_finite = 0.0, measured_rate = 0.0;
  Moments gap, robot_tau, pair_tau;
  double ks_gap = 0.0, ks_gap_critical = 0.0;
  double rho_robot = 0.0, rho_pair = 0.0;
  double ks_tau = 0.0, ks_tau_critical = 0.0, ks_pair = 0.0, ks_pair_critical = 0.0;
};

/// The histograms of the figures, with the model's and the fitted densities at their centres.
struct Densities {
  Histogram gap, tau;
  std::vector<double> gap_model, gap_fit, tau_paper, tau_fit;
};

Setup set_up(const EncountersOptions& o, const std::string& path) {
  const auto file = scenario::load(path);
  const double file_area = file.arena.width * file.arena.height;
  const double density = file.arena.robots_inside / file_area;
  Setup u;
  u.robots = o.robots.value_or(o.common.quick ? 60 : 200);
  u.duration = o.duration.value_or(o.common.quick ? 20.0 : 100.0);
  u.side = std::sqrt(u.robots / density);
  std::vector<std::string> overrides = {"arena.robots_inside=" + std::to_string(u.robots),
                                        "arena.width=" + std::to_string(u.side),
                                        "arena.height=" + std::to_string(u.side),
                                        "arena.record_encounters=true"};
  if (o.seed) overrides.push_back("seed=" + std::to_string(*o.seed));
  u.s = scenario::load(path, overrides);
  return u;
}

/// Runs the world: the warm-up, then `duration` seconds; writes intervals.csv and contacts.csv.
Measured simulate(const Setup& u, const std::string& out) {
  auto world = physics::make_world(u.s.arena);
  const double dt = u.s.arena.tick_dt;
  for (long k = 0; k < std::lround(warm_up / dt); ++k) world->step_tick();
  world->take_contact_records();
  Measured m;
  std::vector<double> last(u.robots, -1.0);
  CsvWriter interval_csv(out + "/intervals.csv", {"robot", "onset_time", "interval"});
  CsvWriter contact_csv(out + "/contacts.csv", {"kind", "robot", "other", "start", "end", "duration"});
  std::fprintf(stderr, "retreat-experiment: encounters: %u robots in a %.2f m square (λ = %.3f), %.0f s "
                       "after %.0f s of warm-up\n", u.robots, u.side, u.robots / (u.side * u.side), u.duration, warm_up);
  for (long k = 0; k < std::lround(u.duration / dt); ++k) {
    if (const int signo = stop_signal.load(); signo != 0) throw Stopped{signo};
    world->step_tick();
    for (const auto& f : world->frames()) {
      for (std::uint32_t n = 0; n < f.new_onsets; ++n) {
        if (last[f.id] >= 0.0) {
          m.intervals.push_back(f.time - last[f.id]);
          interval_csv.row({f.id, f.time, f.time - last[f.id]});
        }
        last[f.id] = f.time;
        m.onsets += 1.0;
      }
    }
    for (const auto& c : world->take_contact_records()) {
      const bool episode = c.other == physics::no_robot;
      (episode ? m.robot_durations : m.pair_durations).push_back(c.end - c.start);
      contact_csv.row({episode ? "robot" : "pair", c.robot, episode ? nlohmann::json("") : nlohmann::json(c.other),
                       c.start, c.end, c.end - c.start});
    }
  }
  interval_csv.close();
  contact_csv.close();
  if (m.intervals.size() < 2 || m.robot_durations.size() < 2) {
    throw RunFailure("encounters: too few encounters to fit (" + std::to_string(m.intervals.size()) +
                     " intervals); give more --robots or --duration");
  }
  return m;
}

Fit fit(const Setup& u, const Measured& m) {
  const double dt = u.s.arena.tick_dt;
  Fit f;
  f.onsets = m.onsets;
  f.area = u.side * u.side;
  f.lambda = u.robots / f.area;
  f.omega_paper = model::omega_c(u.s.model, f.lambda);  // 4δ(4/π)vλ
  f.omega_finite = model::swept_rate(u.s.model) * (u.robots - 1) / f.area;  // MODEL.md §7.1
  f.measured_rate = m.onsets / (u.robots * u.duration);
  f.gap = moments(m.intervals);
  // Each encounter is in two robots' sequences: n/2 independent-ish intervals (conservative);
  // sampling at dt moves the empirical CDF by at most Ω_c·dt.
  f.ks_gap = ks_exponential(m.intervals, f.omega_paper);
  f.ks_gap_critical = ks_critical_specified(static_cast<double>(f.gap.n) / 2.0) + f.omega_paper * dt;
  f.robot_tau = moments(m.robot_durations);
  f.pair_tau = moments(m.pair_durations);
  f.rho_robot = 1.0 / f.robot_tau.mean;
  f.rho_pair = 1.0 / f.pair_tau.mean;
  f.ks_tau = ks_exponential(m.robot_durations, f.rho_robot);
  f.ks_tau_critical = ks_critical_fitted(static_cast<double>(f.robot_tau.n)) + f.rho_robot * dt;
  f.ks_pair = ks_exponential(m.pair_durations, f.rho_pair);
  f.ks_pair_critical = ks_critical_fitted(static_cast<double>(f.pair_tau.n)) + f.rho_pair * dt;
  return f;
}

/// results.json.
void write_results(const std::string& out, const Setup& u, const Fit& f) {
  nlohmann::json r;
  r["scenario"] = u.s.name;
  r["seed"] = u.s.seed;
  r["robots"] = u.robots;
  r["area"] = f.area;
  r["lambda"] = f.lambda;
  r["delta"] = u.s.model.delta;
  r["v"] = u.s.model.v;
  r["dt"] = u.s.arena.tick_dt;
  r["warm_up"] = warm_up;
  r["duration"] = u.duration;
  r["onsets"] = f.onsets;
  r["onset_rate"] = {{"measured", f.measured_rate},
                     {"formula", f.omega_paper},
                     {"formula_finite_population", f.omega_finite},
                     {"ratio_to_formula", f.measured_rate / f.omega_paper},
                     {"ratio_to_finite_population_formula", f.measured_rate / f.omega_finite}};
  r["inter_encounter"] = {{"n", f.gap.n}, {"mean", f.gap.mean}, {"se", f.gap.se}, {"sd", f.gap.sd},
                          {"formula_mean", 1.0 / f.omega_paper}, {"fitted_rate", 1.0 / f.gap.mean},
                          {"ks_against_formula", f.ks_gap}, {"ks_critical_5pct", f.ks_gap_critical},
                          {"ks_passes", f.ks_gap <= f.ks_gap_critical}};
  // se of ρ̂ = 1/mean by the delta method: ρ · se(mean)/mean.
  const auto tau_json = [&](const Moments& m, double rho, double ks, double critical) {
    return nlohmann::json{{"n", m.n}, {"mean", m.mean}, {"se", m.se}, {"sd", m.sd}, {"cv", m.sd / m.mean},
                          {"rho", rho}, {"rho_se", rho * m.se / m.mean},
                          {"ks_against_fitted", ks}, {"ks_critical_5pct", critical}, {"ks_passes", ks <= critical}};
  };
  r["resolution"] = {{"robot", tau_json(f.robot_tau, f.rho_robot, f.ks_tau, f.ks_tau_critical)},
                     {"pair", tau_json(f.pair_tau, f.rho_pair, f.ks_pair, f.ks_pair_critical)},
                     {"paper_rho", paper_rho}};
  write_json(out + "/results.json", r);
}

/// The histograms and the densities against them; writes histograms.csv.
Densities write_histograms(const std::string& out, const Measured& m, const Fit& f) {
  const auto exp_density = [](double rate, const std::vector<double>& x) {
    std::vector<double> y;
    for (const double v : x) y.push_back(rate * std::exp(-rate * v));
    return y;
  };
  Densities d;
  d.gap = histogram(m.intervals, quantile(m.intervals, 0.99), bins);
  d.tau = histogram(m.robot_durations, quantile(m.robot_durations, 0.99), bins);
  CsvWriter hist_csv(out + "/histograms.csv", {"kind", "centre", "measured", "model", "fitted"});
  d.gap_model = exp_density(f.omega_paper, d.gap.centres);
  d.gap_fit = exp_density(1.0 / f.gap.mean, d.gap.centres);
  d.tau_paper = exp_density(paper_rho, d.tau.centres);
  d.tau_fit = exp_density(f.rho_robot, d.tau.centres);
  for (std::size_t k = 0; k < d.gap.centres.size(); ++k) {
    hist_csv.row({"inter_encounter", d.gap.centres[k], d.gap.density[k], d.gap_model[k], d.gap_fit[k]});
  }
  for (std::size_t k = 0; k < d.tau.centres.size(); ++k) {
    hist_csv.row({"resolution", d.tau.centres[k], d.tau.density[k], d.tau_paper[k], d.tau_fit[k]});
  }
  hist_csv.close();
  return d;
}

nlohmann::json gap_figure(const Fit& f, const Densities& d) {
  char text[600];
  auto f1 = figure("inter-encounter-times", "Inter-encounter times",
                   "", "time between a robot's encounter onsets τ_c [s]", "probability density [1/s]");
  std::snprintf(text, sizeof text,
                "%zu intervals, mean %.4f ± %.4f s (formula 1/Ω_c = %.4f s). KS distance to Exp(Ω_c) "
                "%.4f, 5%% critical value %.4f: %s.", f.gap.n, f.gap.mean, f.gap.se, 1.0 / f.omega_paper, f.ks_gap,
                f.ks_gap_critical, f.ks_gap <= f.ks_gap_critical ? "consistent" : "rejected");
  f1["note"] = text;
  f1["x_min"] = 0.0;
  f1["series"].push_back(series("measured", "bars", d.gap.centres, d.gap.density));
  f1["series"].push_back(series("Exp(Ω_c), Ω_c = 4δ(4/π)vλ = " + fixed(f.omega_paper, 3) + "/s", "line",
                                d.gap.centres, d.gap_model));
  f1["series"].push_back(series("Exp(fitted " + fixed(1.0 / f.gap.mean, 3) + "/s)", "line", d.gap.centres, d.gap_fit,
                                true));
  return f1;
}

nlohmann::json resolution_figure(const Fit& f, const Densities& d) {
  char text[600];
  auto f2 = figure("resolution-times", "Encounter resolution times",
                   "", "time until a robot has no one within 2δ τ_r [s]", "probability density [1/s]");
  std::snprintf(text, sizeof text,
                "%zu contact episodes, mean %.4f ± %.4f s: fitted ρ = %.3f ± %.3f /s (paper 2.44). KS "
                "distance to Exp(fitted ρ) %.4f, 5%% critical value %.4f: %s; coefficient of variation "
                "%.2f (1 for an exponential). Per pair: ρ = %.3f /s.", f.robot_tau.n, f.robot_tau.mean,
                f.robot_tau.se, f.rho_robot, f.rho_robot * f.robot_tau.se / f.robot_tau.mean, f.ks_tau,
                f.ks_tau_critical, f.ks_tau <= f.ks_tau_critical ? "consistent" : "rejected",
                f.robot_tau.sd / f.robot_tau.mean, f.rho_pair);
  f2["note"] = text;
  f2["x_min"] = 0.0;
  f2["series"].push_back(series("measured", "bars", d.tau.centres, d.tau.density));
  f2["series"].push_back(series("Exp(fitted ρ = " + fixed(f.rho_robot, 2) + "/s)", "line", d.tau.centres, d.tau_fit));
  f2["series"].push_back(series("Exp(paper ρ = 2.44/s)", "line", d.tau.centres, d.tau_paper, true));
  return f2;
}

/// report.html.
void write_page(const std::string& out, const Setup& u, const Fit& f, const Densities& d) {
  char text[600];
  std::snprintf(text, sizeof text,
                "%u robots in a %.2f m square (λ = %.3f robots/m², δ = %.2f m, v = %.1f m/s, barrier "
                "certificates), %.0f s measured after %.0f s of warm-up, seed %llu. Onsets per robot per "
                "second: %.4f measured against 4δ(4/π)vλ = %.4f (ratio %.3f; %.3f against the finite-"
                "population rate c(N−1)/|D|).", u.robots, u.side, f.lambda, u.s.model.delta, u.s.model.v,
                u.duration, warm_up, static_cast<unsigned long long>(u.s.seed), f.measured_rate, f.omega_paper,
                f.measured_rate / f.omega_paper, f.measured_rate / f.omega_finite);
  nlohmann::json page = {{"title", "retreat experiment: encounter model"},
                         {"subtitle", "MODEL.md §2 and §6: the paper's encounter-model validation"},
                         {"sections", {{{"heading", "Set-up and onset rate"}, {"text", {text}},
                                        {"figures", {gap_figure(f, d), resolution_figure(f, d)}}}}},
                         {"footer", "Written by retreat-experiment encounters; data in results.json, "
                                    "histograms.csv, intervals.csv, contacts.csv."}};
  report::write_figures_page(page, out + "/report.html");
}

}  // namespace

int run_encounters(const EncountersOptions& o) {
  const auto u = set_up(o, scenario_file(o.common, "validation-encounters.yaml"));
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;
  const auto measured = simulate(u, out);
  const auto f = fit(u, measured);
  write_results(out, u, f);
  write_page(out, u, f, write_histograms(out, measured, f));
  std::fprintf(stderr, "retreat-experiment: encounters: onset rate %.3f× the formula; KS %.4f (critical %.4f); "
                       "fitted ρ = %.3f ± %.3f /s (paper 2.44), KS %.4f (critical %.4f); %s/report.html\n",
               f.measured_rate / f.omega_paper, f.ks_gap, f.ks_gap_critical, f.rho_robot,
               f.rho_robot * f.robot_tau.se / f.robot_tau.mean, f.ks_tau, f.ks_tau_critical, out.c_str());
  return 0;
}

}  // namespace retreat::experiment
