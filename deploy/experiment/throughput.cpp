// `retreat-experiment throughput`: simulated swarm output T(λ)λ over a grid of densities in the
// physical world of retreat::physics (deploy/scenarios/validation-throughput.yaml: v = 0.1,
// δ = 0.11, λ_p = 0.82, λ_d = 0.66; the square is sized for each λ), against the CTMC curve of
// retreat::model with ρ fitted in this world at λ = 0.99 and with the paper's ρ = 2.44. Writes:
//   points.csv    lambda, robots (per seed), side, deliveries (all seeds), output, output_se, ctmc_fitted, ratio_fitted,
//                 ctmc_paper, ratio_paper, rho_robot (ρ fitted at that λ), free_fraction
//   curve.csv     lambda, ctmc_fitted, ctmc_paper
//   results.json;  report.html

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "launch.hpp"
#include "page.hpp"
#include "retreat/report/figures.hpp"
#include "retreat/model/ctmc.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/physics/world.hpp"
#include "retreat/scenario/scenario.hpp"
#include "stats.hpp"
#include "retreat/experiment/subcommands.hpp"

namespace retreat::experiment {
namespace {

constexpr double lambda_fit = 0.99;  // where ρ is fitted, as in the paper
constexpr double paper_rho = 2.44;

struct Point {
  double lambda = 0.0;
  std::uint32_t robots = 0;
  double side = 0.0;
  double deliveries = 0.0;  // over every seed
  double output = 0.0;      // deliveries / (|D| · duration · seeds) [1/(m²·s)]
  double output_se = 0.0;   // from the spread of the robots' delivery counts (all seeds)
  double rho_robot = 0.0;   // 1 / mean contact-episode duration [1/s]
  double free_fraction = 0.0;  // time share of f and l (not in contact), inside robots
};

/// One density over the seeds, pooled: every robot of every seed is one delivery count.
Point simulate(const std::string& path, const SeedRange& seeds, double lambda, std::uint32_t robots, double warm_up,
               double duration) {
  Point p;
  p.lambda = lambda;
  p.robots = robots;
  p.side = std::sqrt(robots / lambda);
  std::vector<double> per_robot;
  double episode_sum = 0.0, episodes = 0.0, free = 0.0, all = 0.0;
  for (auto seed = seeds.first;; ++seed) {
    const auto s = scenario::load(path, {"arena.robots_inside=" + std::to_string(robots),
                                         "arena.width=" + std::to_string(p.side),
                                         "arena.height=" + std::to_string(p.side), "arena.record_encounters=true",
                                         "seed=" + std::to_string(seed)});
    auto world = physics::make_world(s.arena);
    const double dt = s.arena.tick_dt;
    for (long k = 0; k < std::lround(warm_up / dt); ++k) world->step_tick();
    world->take_contact_records();
    std::vector<double> before(robots);
    for (std::uint32_t id = 0; id < robots; ++id) before[id] = static_cast<double>(world->robot_stats(id).deliveries);
    const auto t0 = world->telemetry();
    for (long k = 0; k < std::lround(duration / dt); ++k) {
      if (const int signo = stop_signal.load(); signo != 0) throw Stopped{signo};
      world->step_tick();
      for (const auto& c : world->take_contact_records()) {
        if (c.other != physics::no_robot) continue;
        episode_sum += c.end - c.start;
        episodes += 1.0;
      }
    }
    const auto t1 = world->telemetry();
    for (std::uint32_t id = 0; id < robots; ++id) {
      per_robot.push_back(static_cast<double>(world->robot_stats(id).deliveries) - before[id]);
    }
    p.deliveries += static_cast<double>(t1.deliveries - t0.deliveries);
    for (std::size_t k = 0; k < t1.state_time.size(); ++k) {
      const double span = t1.state_time[k] - t0.state_time[k];
      all += span;
      if (k < 2) free += span;  // f, l (then fc, lc)
    }
    if (seed == seeds.last) break;
  }
  const double area = p.side * p.side;
  const double n = static_cast<double>(seeds.count());
  const auto m = moments(per_robot);
  p.output = p.deliveries / (area * duration * n);
  p.output_se = m.se * robots / (area * duration);
  p.rho_robot = episodes > 0 ? episodes / episode_sum : 0.0;
  p.free_fraction = all > 0 ? free / all : 0.0;
  return p;
}

/// The densities to run: the given or default grid, with λ = 0.99 (where ρ is fitted), sorted.
std::vector<double> densities(const ThroughputOptions& o) {
  auto lambdas = o.lambdas;
  if (lambdas.empty()) {
    lambdas = o.common.quick ? std::vector<double>{0.5, 0.99, 2.0}
                             : std::vector<double>{0.25, 0.5, 0.75, 0.99, 1.5, 2.0, 3.0, 4.0};
  }
  if (std::find(lambdas.begin(), lambdas.end(), lambda_fit) == lambdas.end()) lambdas.push_back(lambda_fit);
  std::sort(lambdas.begin(), lambdas.end());
  return lambdas;
}

/// The run's sizes, defaults resolved.
struct Setup {
  std::vector<double> lambdas;
  std::uint32_t robots = 0;
  double duration = 0.0, warm_up = 0.0;
  SeedRange seeds;
};

/// The CTMC with ρ fitted here and with the paper's ρ.
struct Models {
  model::ModelParams fitted, paper;
  double rho_fitted = 0.0;
};

/// The points as the figures and the table take them.
struct Columns {
  nlohmann::json rows = nlohmann::json::array(), table_rows = nlohmann::json::array();
  std::vector<double> xs, ys, lo, hi, ratio_fit, ratio_paper, rho_at;
};

/// The CTMC curve on a grid up to just past the largest λ.
struct Curve {
  std::vector<double> x, fitted, paper;
};

/// Writes points.csv; returns the points as columns.
Columns write_points(const std::string& out, const std::vector<Point>& points, const Models& m) {
  CsvWriter csv(out + "/points.csv", {"lambda", "robots", "side", "deliveries", "output", "output_se", "ctmc_fitted",
                                      "ratio_fitted", "ctmc_paper", "ratio_paper", "rho_robot", "free_fraction"});
  Columns c;
  for (const auto& p : points) {
    const double cf = model::output(m.fitted, p.lambda), cp = model::output(m.paper, p.lambda);
    csv.row({p.lambda, p.robots, p.side, p.deliveries, p.output, p.output_se, cf, p.output / cf, cp, p.output / cp,
             p.rho_robot, p.free_fraction});
    c.rows.push_back({{"lambda", p.lambda}, {"deliveries", p.deliveries}, {"output", p.output},
                      {"output_se", p.output_se}, {"ctmc_fitted", cf}, {"ratio_fitted", p.output / cf},
                      {"ctmc_paper", cp}, {"ratio_paper", p.output / cp}, {"rho_robot", p.rho_robot},
                      {"free_fraction", p.free_fraction}});
    c.table_rows.push_back({fixed(p.lambda, 2), fixed(p.output * 1000.0, 3) + " ± " + fixed(p.output_se * 1000.0, 3),
                            fixed(cf * 1000.0, 3), fixed(p.output / cf, 3), fixed(cp * 1000.0, 3),
                            fixed(p.output / cp, 3), fixed(p.rho_robot, 3), fixed(p.free_fraction, 3)});
    c.xs.push_back(p.lambda);
    c.ys.push_back(p.output);
    c.lo.push_back(p.output - 2.0 * p.output_se);
    c.hi.push_back(p.output + 2.0 * p.output_se);
    c.ratio_fit.push_back(p.output / cf);
    c.ratio_paper.push_back(p.output / cp);
    c.rho_at.push_back(p.rho_robot);
  }
  csv.close();
  return c;
}

/// Writes curve.csv; returns the curve.
Curve write_curve(const std::string& out, double largest_lambda, const Models& m) {
  CsvWriter curve_csv(out + "/curve.csv", {"lambda", "ctmc_fitted", "ctmc_paper"});
  Curve c;
  const double top = 1.05 * largest_lambda;
  for (int k = 0; k <= 200; ++k) {
    const double l = top * k / 200.0;
    c.x.push_back(l);
    c.fitted.push_back(model::output(m.fitted, l));
    c.paper.push_back(model::output(m.paper, l));
    curve_csv.row({l, c.fitted.back(), c.paper.back()});
  }
  curve_csv.close();
  return c;
}

/// The two figures: output against the CTMC, and the ratio with ρ at each λ.
nlohmann::json figures(const Columns& c, const Curve& curve, double rho_fitted) {
  auto f1 = figure("throughput", "Swarm output T(λ)λ against the CTMC",
                   "Deliveries per m² per second in the physical world (points; band ±2 standard errors from the "
                   "robots' delivery counts) and the CTMC's T(λ)λ with ρ fitted here at λ = 0.99 (" +
                       fixed(rho_fitted, 3) + "/s) and with the paper's ρ = 2.44/s.",
                   "robot density λ [robots/m²]", "T(λ)λ [deliveries/(m²·s)]");
  f1["y_min"] = 0.0;
  f1["series"].push_back(band("simulated ±2 se", c.xs, c.lo, c.hi));
  f1["series"].push_back(series("simulated", "points", c.xs, c.ys));
  f1["series"].push_back(series("CTMC, ρ fitted = " + fixed(rho_fitted, 3) + "/s", "line", curve.x, curve.fitted));
  f1["series"].push_back(series("CTMC, ρ = 2.44/s (paper)", "line", curve.x, curve.paper, true));
  for (const auto& [k, color] : {std::pair{0, "#2f7ed8"}, {1, "#2f7ed8"}, {2, "#f28f1c"}, {3, "#7b4fd0"}}) {
    f1["series"][k]["color"] = color;
  }
  auto f2 = figure("throughput-ratio", "Simulated over CTMC",
                   "The ratio of the simulated output to the CTMC's, and the robot-level ρ fitted at each λ "
                   "(the CTMC assumes one constant ρ).", "robot density λ [robots/m²]", "ratio, or ρ [1/s]");
  f2["y_min"] = 0.0;
  f2["series"].push_back(series("simulated / CTMC (ρ fitted)", "line", c.xs, c.ratio_fit));
  f2["series"].push_back(series("simulated / CTMC (ρ = 2.44)", "line", c.xs, c.ratio_paper, true));
  f2["series"].push_back(series("ρ fitted at this λ [1/s]", "points", c.xs, c.rho_at));
  return {f1, f2};
}

/// report.html.
void write_page(const std::string& out, const Setup& u, const scenario::Scenario& base, const Columns& c,
                const Curve& curve, double rho_fitted) {
  nlohmann::json table = {{"title", "Points (outputs in 10⁻³ deliveries/(m²·s))"},
                          {"columns", {"λ", "simulated ± se", "CTMC ρ fitted", "ratio", "CTMC ρ 2.44", "ratio",
                                       "ρ at λ", "free fraction"}},
                          {"rows", c.table_rows}};
  char text[400];
  std::snprintf(text, sizeof text,
                "%u robots per density in a square sized for λ, v = %.2f m/s, δ = %.2f m, λ_p = %.2f, λ_d = %.2f, "
                "barrier certificates; %.0f s measured after %.0f s of warm-up, seeds %s (pooled).", u.robots,
                base.model.v, base.model.delta, base.model.lambda_p, base.model.lambda_d, u.duration, u.warm_up,
                u.seeds.text().c_str());
  nlohmann::json page = {{"title", "retreat experiment: throughput"},
                         {"subtitle", "MODEL.md §3 and §6: the paper's throughput curve"},
                         {"sections", {{{"heading", "Set-up"}, {"text", {text}},
                                        {"figures", figures(c, curve, rho_fitted)}, {"tables", {table}}}}},
                         {"footer", "Written by retreat-experiment throughput; data in results.json, points.csv, curve.csv."}};
  report::write_figures_page(page, out + "/report.html");
}

}  // namespace

int run_throughput(const ThroughputOptions& o) {
  const auto path = scenario_file(o.common, "validation-throughput.yaml");
  const auto base = scenario::load(path);
  Setup u;
  u.lambdas = densities(o);
  u.robots = o.robots.value_or(o.common.quick ? 40 : 200);
  u.duration = o.duration.value_or(o.common.quick ? 500.0 : 2500.0);
  // Two delivery cycles (1/Ω_p + 1/Ω_d ≈ 124 s at these parameters) before measuring.
  u.warm_up = o.common.quick ? 100.0 : 250.0;
  u.seeds = o.seeds.value_or(SeedRange{base.seed, base.seed});
  make_run_dir(o.common.out_dir);
  const std::string out = o.common.out_dir;

  std::vector<Point> points;
  for (const double l : u.lambdas) {
    std::fprintf(stderr, "retreat-experiment: throughput: λ = %.3f, %u robots, %.0f s, seeds %s\n", l, u.robots,
                 u.warm_up + u.duration, u.seeds.text().c_str());
    points.push_back(simulate(path, u.seeds, l, u.robots, u.warm_up, u.duration));
  }
  const auto fit = *std::find_if(points.begin(), points.end(), [](const Point& p) { return p.lambda == lambda_fit; });
  Models m{base.model, base.model, fit.rho_robot};
  m.fitted.rho = fit.rho_robot;
  m.paper.rho = paper_rho;

  const auto columns = write_points(out, points, m);
  const auto curve = write_curve(out, u.lambdas.back(), m);
  nlohmann::json r = {{"scenario", base.name}, {"robots", u.robots}, {"warm_up", u.warm_up}, {"duration", u.duration},
                      {"seeds", u.seeds.text()}, {"v", base.model.v}, {"delta", base.model.delta},
                      {"lambda_p", base.model.lambda_p}, {"lambda_d", base.model.lambda_d},
                      {"rho_fitted", fit.rho_robot}, {"rho_fitted_at", lambda_fit}, {"rho_paper", paper_rho},
                      {"points", columns.rows}};
  write_json(out + "/results.json", r);
  write_page(out, u, base, columns, curve, fit.rho_robot);
  for (const auto& p : points) {
    std::fprintf(stderr, "retreat-experiment: throughput: λ = %.2f: simulated/CTMC %.3f (ρ fitted %.3f), %.3f (ρ 2.44)\n",
                 p.lambda, p.output / model::output(m.fitted, p.lambda), fit.rho_robot,
                 p.output / model::output(m.paper, p.lambda));
  }
  std::fprintf(stderr, "retreat-experiment: throughput: %s/report.html\n", out.c_str());
  return 0;
}

}  // namespace retreat::experiment
