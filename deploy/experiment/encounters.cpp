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
#include "subcommands.hpp"

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

}  // namespace

int run_encounters(const EncountersOptions& o) {
  const auto path = scenario_file(o.common, "validation-encounters.yaml");
  const auto file = scenario::load(path);
  const double file_area = file.arena.width * file.arena.height;
  const double density = file.arena.robots_inside / file_area;
  const std::uint32_t robots = o.robots.value_or(o.common.quick ? 60 : 200);
  const double duration = o.duration.value_or(o.common.quick ? 20.0 : 100.0);
  const double side = std::sqrt(robots / density);
  std::vector<std::string> overrides = {"arena.robots_inside=" + std::to_string(robots),
                                        "arena.width=" + std::to_string(side),
                                        "arena.height=" + std::to_string(side),
                                        "arena.record_encounters=true"};
  if (o.seed) overrides.push_back("seed=" + std::to_string(*o.seed));
  const auto s = scenario::load(path, overrides);
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;

  // --- simulate ----------------------------------------------------------------------------------
  auto world = physics::make_world(s.arena);
  const double dt = s.arena.tick_dt;
  for (long k = 0; k < std::lround(warm_up / dt); ++k) world->step_tick();
  world->take_contact_records();
  std::vector<double> last(robots, -1.0), intervals, robot_durations, pair_durations;
  double onsets = 0.0;
  CsvWriter interval_csv(out + "/intervals.csv", {"robot", "onset_time", "interval"});
  CsvWriter contact_csv(out + "/contacts.csv", {"kind", "robot", "other", "start", "end", "duration"});
  std::fprintf(stderr, "retreat-experiment: encounters: %u robots in a %.2f m square (λ = %.3f), %.0f s "
                       "after %.0f s of warm-up\n", robots, side, robots / (side * side), duration, warm_up);
  for (long k = 0; k < std::lround(duration / dt); ++k) {
    if (const int signo = stop_signal.load(); signo != 0) throw Stopped{signo};
    world->step_tick();
    for (const auto& f : world->frames()) {
      for (std::uint32_t n = 0; n < f.new_onsets; ++n) {
        if (last[f.id] >= 0.0) {
          intervals.push_back(f.time - last[f.id]);
          interval_csv.row({f.id, f.time, f.time - last[f.id]});
        }
        last[f.id] = f.time;
        onsets += 1.0;
      }
    }
    for (const auto& c : world->take_contact_records()) {
      const bool episode = c.other == physics::no_robot;
      (episode ? robot_durations : pair_durations).push_back(c.end - c.start);
      contact_csv.row({episode ? "robot" : "pair", c.robot, episode ? nlohmann::json("") : nlohmann::json(c.other),
                       c.start, c.end, c.end - c.start});
    }
  }
  interval_csv.close();
  contact_csv.close();
  if (intervals.size() < 2 || robot_durations.size() < 2) {
    throw RunFailure("encounters: too few encounters to fit (" + std::to_string(intervals.size()) +
                     " intervals); give more --robots or --duration");
  }

  // --- fit ---------------------------------------------------------------------------------------
  const double area = side * side;
  const double lambda = robots / area;
  const double omega_paper = model::omega_c(s.model, lambda);  // 4δ(4/π)vλ
  const double omega_finite = model::swept_rate(s.model) * (robots - 1) / area;  // MODEL.md §7.1
  const double measured_rate = onsets / (robots * duration);
  const auto gap = moments(intervals);
  // Each encounter is in two robots' sequences: n/2 independent-ish intervals (conservative);
  // sampling at dt moves the empirical CDF by at most Ω_c·dt.
  const double ks_gap = ks_exponential(intervals, omega_paper);
  const double ks_gap_critical = ks_critical_specified(static_cast<double>(gap.n) / 2.0) + omega_paper * dt;
  const auto robot_tau = moments(robot_durations);
  const auto pair_tau = moments(pair_durations);
  const double rho_robot = 1.0 / robot_tau.mean;
  const double rho_pair = 1.0 / pair_tau.mean;
  const double ks_tau = ks_exponential(robot_durations, rho_robot);
  const double ks_tau_critical = ks_critical_fitted(static_cast<double>(robot_tau.n)) + rho_robot * dt;
  const double ks_pair = ks_exponential(pair_durations, rho_pair);
  const double ks_pair_critical = ks_critical_fitted(static_cast<double>(pair_tau.n)) + rho_pair * dt;

  nlohmann::json r;
  r["scenario"] = s.name;
  r["seed"] = s.seed;
  r["robots"] = robots;
  r["area"] = area;
  r["lambda"] = lambda;
  r["delta"] = s.model.delta;
  r["v"] = s.model.v;
  r["dt"] = dt;
  r["warm_up"] = warm_up;
  r["duration"] = duration;
  r["onsets"] = onsets;
  r["onset_rate"] = {{"measured", measured_rate},
                     {"formula", omega_paper},
                     {"formula_finite_population", omega_finite},
                     {"ratio_to_formula", measured_rate / omega_paper},
                     {"ratio_to_finite_population_formula", measured_rate / omega_finite}};
  r["inter_encounter"] = {{"n", gap.n}, {"mean", gap.mean}, {"se", gap.se}, {"sd", gap.sd},
                          {"formula_mean", 1.0 / omega_paper}, {"fitted_rate", 1.0 / gap.mean},
                          {"ks_against_formula", ks_gap}, {"ks_critical_5pct", ks_gap_critical},
                          {"ks_passes", ks_gap <= ks_gap_critical}};
  // se of ρ̂ = 1/mean by the delta method: ρ · se(mean)/mean.
  const auto tau_json = [&](const Moments& m, double rho, double ks, double critical) {
    return nlohmann::json{{"n", m.n}, {"mean", m.mean}, {"se", m.se}, {"sd", m.sd}, {"cv", m.sd / m.mean},
                          {"rho", rho}, {"rho_se", rho * m.se / m.mean},
                          {"ks_against_fitted", ks}, {"ks_critical_5pct", critical}, {"ks_passes", ks <= critical}};
  };
  r["resolution"] = {{"robot", tau_json(robot_tau, rho_robot, ks_tau, ks_tau_critical)},
                     {"pair", tau_json(pair_tau, rho_pair, ks_pair, ks_pair_critical)},
                     {"paper_rho", paper_rho}};
  write_json(out + "/results.json", r);

  // --- histograms, figures -----------------------------------------------------------------------
  const auto gap_hist = histogram(intervals, quantile(intervals, 0.99), bins);
  const auto tau_hist = histogram(robot_durations, quantile(robot_durations, 0.99), bins);
  const auto exp_density = [](double rate, const std::vector<double>& x) {
    std::vector<double> y;
    for (const double v : x) y.push_back(rate * std::exp(-rate * v));
    return y;
  };
  CsvWriter hist_csv(out + "/histograms.csv", {"kind", "centre", "measured", "model", "fitted"});
  const auto gap_model = exp_density(omega_paper, gap_hist.centres);
  const auto gap_fit = exp_density(1.0 / gap.mean, gap_hist.centres);
  const auto tau_paper = exp_density(paper_rho, tau_hist.centres);
  const auto tau_fit = exp_density(rho_robot, tau_hist.centres);
  for (std::size_t k = 0; k < gap_hist.centres.size(); ++k) {
    hist_csv.row({"inter_encounter", gap_hist.centres[k], gap_hist.density[k], gap_model[k], gap_fit[k]});
  }
  for (std::size_t k = 0; k < tau_hist.centres.size(); ++k) {
    hist_csv.row({"resolution", tau_hist.centres[k], tau_hist.density[k], tau_paper[k], tau_fit[k]});
  }
  hist_csv.close();

  char text[600];
  auto f1 = figure("inter-encounter-times", "Inter-encounter times",
                   "", "time between a robot's encounter onsets τ_c [s]", "probability density [1/s]");
  std::snprintf(text, sizeof text,
                "%zu intervals, mean %.4f ± %.4f s (formula 1/Ω_c = %.4f s). KS distance to Exp(Ω_c) "
                "%.4f, 5%% critical value %.4f: %s.", gap.n, gap.mean, gap.se, 1.0 / omega_paper, ks_gap,
                ks_gap_critical, ks_gap <= ks_gap_critical ? "consistent" : "rejected");
  f1["note"] = text;
  f1["x_min"] = 0.0;
  f1["series"].push_back(series("measured", "bars", gap_hist.centres, gap_hist.density));
  f1["series"].push_back(series("Exp(Ω_c), Ω_c = 4δ(4/π)vλ = " + fixed(omega_paper, 3) + "/s", "line",
                                gap_hist.centres, gap_model));
  f1["series"].push_back(series("Exp(fitted " + fixed(1.0 / gap.mean, 3) + "/s)", "line", gap_hist.centres, gap_fit, true));
  auto f2 = figure("resolution-times", "Encounter resolution times",
                   "", "time until a robot has no one within 2δ τ_r [s]", "probability density [1/s]");
  std::snprintf(text, sizeof text,
                "%zu contact episodes, mean %.4f ± %.4f s: fitted ρ = %.3f ± %.3f /s (paper 2.44). KS "
                "distance to Exp(fitted ρ) %.4f, 5%% critical value %.4f: %s; coefficient of variation "
                "%.2f (1 for an exponential). Per pair: ρ = %.3f /s.", robot_tau.n, robot_tau.mean, robot_tau.se,
                rho_robot, rho_robot * robot_tau.se / robot_tau.mean, ks_tau, ks_tau_critical,
                ks_tau <= ks_tau_critical ? "consistent" : "rejected", robot_tau.sd / robot_tau.mean, rho_pair);
  f2["note"] = text;
  f2["x_min"] = 0.0;
  f2["series"].push_back(series("measured", "bars", tau_hist.centres, tau_hist.density));
  f2["series"].push_back(series("Exp(fitted ρ = " + fixed(rho_robot, 2) + "/s)", "line", tau_hist.centres, tau_fit));
  f2["series"].push_back(series("Exp(paper ρ = 2.44/s)", "line", tau_hist.centres, tau_paper, true));
  std::snprintf(text, sizeof text,
                "%u robots in a %.2f m square (λ = %.3f robots/m², δ = %.2f m, v = %.1f m/s, barrier "
                "certificates), %.0f s measured after %.0f s of warm-up, seed %llu. Onsets per robot per "
                "second: %.4f measured against 4δ(4/π)vλ = %.4f (ratio %.3f; %.3f against the finite-"
                "population rate c(N−1)/|D|).", robots, side, lambda, s.model.delta, s.model.v, duration,
                warm_up, static_cast<unsigned long long>(s.seed), measured_rate, omega_paper,
                measured_rate / omega_paper, measured_rate / omega_finite);
  nlohmann::json page = {{"title", "retreat experiment: encounter model"},
                         {"subtitle", "MODEL.md §2 and §6: the paper's encounter-model validation"},
                         {"sections", {{{"heading", "Set-up and onset rate"}, {"text", {text}},
                                        {"figures", {f1, f2}}}}},
                         {"footer", "Written by retreat-experiment encounters; data in results.json, "
                                    "histograms.csv, intervals.csv, contacts.csv."}};
  report::write_figures_page(page, out + "/report.html");
  std::fprintf(stderr, "retreat-experiment: encounters: onset rate %.3f× the formula; KS %.4f (critical %.4f); "
                       "fitted ρ = %.3f ± %.3f /s (paper 2.44), KS %.4f (critical %.4f); %s/report.html\n",
               measured_rate / omega_paper, ks_gap, ks_gap_critical, rho_robot,
               rho_robot * robot_tau.se / robot_tau.mean, ks_tau, ks_tau_critical, out.c_str());
  return 0;
}

}  // namespace retreat::experiment
