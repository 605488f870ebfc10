#include "retreat/report/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "page_parts.hpp"
#include "retreat/core/paths.hpp"
#include "retreat/report/run_info.hpp"
#include "retreat/model/ctmc.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::report {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using detail::asset_text;
using detail::html_escape;
using detail::script_json;

constexpr double no_robot = 4294967295.0;  // physics::no_robot: a per-robot contact episode

/// A CSV file of numbers with a header line.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  /// Column index of `name`, or -1.
  int column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
  int require(const std::string& name, const std::string& file) const {
    const int c = column(name);
    if (c < 0) throw std::runtime_error(file + ": no column '" + name + "'");
    return c;
  }
};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

/// Reads a numeric CSV; a row that does not parse completely (a line being written) ends it.
Table read_table(const std::string& path) {
  // retreat::read_file: a directory in the file's place is refused here, naming it, where an
  // std::ifstream's first read would throw a stream error that names nothing.
  auto text = retreat::read_file(path);
  if (!text) throw std::runtime_error(path + ": cannot read it as a file");
  std::istringstream in(std::move(*text));
  Table t;
  std::string line;
  if (!std::getline(in, line)) return t;
  t.header = split(line);
  while (std::getline(in, line)) {
    if (in.eof()) break;  // no newline at the end: possibly half a row
    const auto cells = split(line);
    if (cells.size() != t.header.size()) break;
    std::vector<double> row;
    row.reserve(cells.size());
    bool ok = true;
    for (const auto& c : cells) {
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      if (c.empty() || end != c.c_str() + c.size()) {
        ok = false;
        break;
      }
      row.push_back(v);
    }
    if (!ok) break;
    t.rows.push_back(std::move(row));
  }
  return t;
}

/// Rounds for the page (the report is for the eye; 6 significant digits keep it small).
double round6(double v) {
  if (!std::isfinite(v) || v == 0.0) return v;
  const double scale = std::pow(10.0, 5 - std::floor(std::log10(std::fabs(v))));
  return std::round(v * scale) / scale;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}

std::vector<std::string> run_dirs_of(const std::string& dir) {
  if (fs::exists(dir + "/telemetry.csv")) return {dir};
  std::vector<std::pair<long, std::string>> seeds;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const auto name = e.path().filename().string();
    if (!e.is_directory() || name.rfind("seed_", 0) != 0) continue;
    if (!fs::exists(e.path() / "telemetry.csv")) continue;
    seeds.emplace_back(std::strtol(name.c_str() + 5, nullptr, 10), e.path().string());
  }
  std::sort(seeds.begin(), seeds.end());
  std::vector<std::string> out;
  for (auto& s : seeds) out.push_back(std::move(s.second));
  if (out.empty()) {
    throw std::runtime_error("'" + dir + "': no telemetry.csv, neither here nor in seed_* directories");
  }
  return out;
}

struct Run {
  std::string dir;
  Table telemetry;
  int time = -1, inside = -1, deliveries = -1, density = -1;
  double end_time() const { return telemetry.rows.empty() ? 0.0 : telemetry.rows.back()[static_cast<std::size_t>(time)]; }
  double at(std::size_t row, int column) const { return telemetry.rows[row][static_cast<std::size_t>(column)]; }
};

json population_json(const std::vector<Run>& runs, double& t_end) {
  t_end = 0.0;
  std::size_t most_rows = 0;
  for (const auto& r : runs) {
    t_end = std::max(t_end, r.end_time());
    most_rows = std::max(most_rows, r.telemetry.rows.size());
  }
  const std::size_t points = std::max<std::size_t>(2, std::min<std::size_t>(1000, most_rows));
  const double step = t_end / static_cast<double>(points - 1);
  json time = json::array(), mean = json::array(), lo = json::array(), hi = json::array();
  std::vector<std::size_t> cursor(runs.size(), 0);
  for (std::size_t k = 0; k < points; ++k) {
    const double t = step * static_cast<double>(k);
    double sum = 0.0, mn = std::numeric_limits<double>::infinity(), mx = -mn;
    int n = 0;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& r = runs[i];
      if (r.telemetry.rows.empty() || t > r.end_time() + 1e-9) continue;
      auto& c = cursor[i];
      while (c + 1 < r.telemetry.rows.size() && r.at(c + 1, r.time) <= t + 1e-9) ++c;
      const double v = r.at(c, r.inside);
      sum += v;
      mn = std::min(mn, v);
      mx = std::max(mx, v);
      ++n;
    }
    time.push_back(round6(t));
    mean.push_back(n > 0 ? json(round6(sum / n)) : json(nullptr));
    lo.push_back(n > 0 ? json(mn) : json(nullptr));
    hi.push_back(n > 0 ? json(mx) : json(nullptr));
  }
  return {{"time", time}, {"mean", mean}, {"min", lo}, {"max", hi}, {"seeds", runs.size()}};
}

json throughput_json(const std::vector<Run>& runs, double t_end, const scenario::Scenario& s,
                     double area, double robots) {
  // About 30 windows over the run, none shorter than 20 s (a few deliveries each).
  const double window = std::max(t_end / 30.0, 20.0);
  json points = json::array();
  double n_max = robots;
  for (const auto& r : runs) {
    const auto& rows = r.telemetry.rows;
    std::size_t i = 0;
    for (double start = 0.0; start + window <= r.end_time() + 1e-9; start += window) {
      while (i < rows.size() && r.at(i, r.time) < start - 1e-9) ++i;
      std::size_t j = i;
      double sum = 0.0;
      std::size_t n = 0;
      while (j < rows.size() && r.at(j, r.time) < start + window - 1e-9) {
        sum += r.at(j, r.inside);
        ++n;
        ++j;
      }
      if (n < 2 || j >= rows.size()) continue;
      const double span = r.at(j, r.time) - r.at(i, r.time);
      if (span <= 0.0) continue;
      const double rate = (r.at(j, r.deliveries) - r.at(i, r.deliveries)) / span;
      const double mean_n = sum / static_cast<double>(n);
      n_max = std::max(n_max, mean_n);
      points.push_back({round6(mean_n), round6(rate)});
    }
  }
  json curve = json::array();
  const double top = 1.25 * std::max(n_max, 1.0);
  constexpr int steps = 120;
  for (int k = 0; k <= steps; ++k) {
    const double n = top * k / steps;
    curve.push_back({round6(n), round6(model::output(s.model, n / area) * area)});
  }
  return {{"window", round6(window)}, {"points", points}, {"curve", curve}};
}

json encounters_json(const std::vector<Run>& runs, const scenario::Scenario& s) {
  std::vector<double> gaps;
  double density_sum = 0.0, density_time = 0.0;
  bool any_file = false;
  for (const auto& r : runs) {
    const auto path = r.dir + "/encounters.csv";
    if (!fs::exists(path)) continue;
    any_file = true;
    const auto t = read_table(path);
    const int robot = t.require("robot", path), other = t.require("other", path),
              onset = t.require("onset_time", path);
    bool pairs = false;
    for (const auto& row : t.rows) pairs = pairs || row[static_cast<std::size_t>(other)] != no_robot;
    std::map<std::uint64_t, std::vector<double>> onsets;
    for (const auto& row : t.rows) {
      const double o = row[static_cast<std::size_t>(other)];
      const double at = row[static_cast<std::size_t>(onset)];
      if (!std::isfinite(at)) continue;
      if (pairs) {
        if (o == no_robot) continue;
        onsets[static_cast<std::uint64_t>(row[static_cast<std::size_t>(robot)])].push_back(at);
        onsets[static_cast<std::uint64_t>(o)].push_back(at);
      } else {
        onsets[static_cast<std::uint64_t>(row[static_cast<std::size_t>(robot)])].push_back(at);
      }
    }
    for (auto& [id, v] : onsets) {
      std::sort(v.begin(), v.end());
      for (std::size_t k = 1; k < v.size(); ++k) gaps.push_back(v[k] - v[k - 1]);
    }
    // Mean density while robots were inside, weighted by time.
    for (std::size_t k = 1; k < r.telemetry.rows.size(); ++k) {
      const double span = r.at(k, r.time) - r.at(k - 1, r.time);
      if (r.at(k - 1, r.inside) <= 0) continue;
      density_sum += r.at(k - 1, r.density) * span;
      density_time += span;
    }
  }
  if (!any_file) return nullptr;
  if (gaps.size() < 2) return {{"gaps", gaps.size()}, {"bins", nullptr}};
  double sum = 0.0;
  for (double g : gaps) sum += g;
  const double mean_gap = sum / static_cast<double>(gaps.size());
  const double upper = std::max(quantile(gaps, 0.99), 1e-9);
  constexpr int bins = 30;
  const double width = upper / bins;
  std::vector<double> counts(bins, 0.0);
  for (double g : gaps) {
    const auto k = static_cast<int>(std::floor(g / width));
    if (k >= 0 && k < bins) counts[static_cast<std::size_t>(k)] += 1.0;
  }
  json hist = json::array();
  for (int k = 0; k < bins; ++k) {
    hist.push_back({round6((k + 0.5) * width),
                    round6(counts[static_cast<std::size_t>(k)] / (static_cast<double>(gaps.size()) * width))});
  }
  const double mean_density = density_time > 0 ? density_sum / density_time : 0.0;
  return {{"bin_width", round6(width)},
          {"bins", hist},
          {"gaps", gaps.size()},
          {"mean_gap", round6(mean_gap)},
          {"fitted_rate", round6(1.0 / mean_gap)},
          {"model_rate", round6(model::omega_c(s.model, mean_density))},
          {"mean_density", round6(mean_density)}};
}

json estimates_json(const std::vector<Run>& runs, double t_end, double status_period) {
  const double width = std::max(status_period, t_end / 300.0);
  const auto bins = static_cast<std::size_t>(std::floor(t_end / width)) + 1;
  std::vector<std::vector<double>> values(bins);
  std::vector<double> density_sum(bins, 0.0), density_n(bins, 0.0);
  std::map<std::uint64_t, bool> agents;
  bool any_file = false;
  for (const auto& r : runs) {
    const auto path = r.dir + "/agent_status.csv";
    if (!fs::exists(path)) continue;
    any_file = true;
    const auto t = read_table(path);
    const int time = t.require("time", path), robot = t.require("robot", path),
              deciding = t.require("deciding", path), retreating = t.require("retreating", path),
              lambda = t.require("lambda_hat", path);
    for (const auto& row : t.rows) {
      if (row[static_cast<std::size_t>(deciding)] == 0.0 || row[static_cast<std::size_t>(retreating)] != 0.0) continue;
      const double at = row[static_cast<std::size_t>(time)];
      if (!(at >= 0.0)) continue;
      const auto k = std::min(bins - 1, static_cast<std::size_t>(std::floor(at / width)));
      values[k].push_back(row[static_cast<std::size_t>(lambda)]);
      agents[static_cast<std::uint64_t>(row[static_cast<std::size_t>(robot)])] = true;
    }
    for (std::size_t k = 0; k < r.telemetry.rows.size(); ++k) {
      const auto b = std::min(bins - 1, static_cast<std::size_t>(std::floor(r.at(k, r.time) / width)));
      density_sum[b] += r.at(k, r.density);
      density_n[b] += 1.0;
    }
  }
  if (!any_file) return nullptr;
  json time = json::array(), mean = json::array(), low = json::array(), high = json::array(),
       truth = json::array();
  for (std::size_t k = 0; k < bins; ++k) {
    time.push_back(round6((static_cast<double>(k) + 0.5) * width));
    if (values[k].empty()) {
      mean.push_back(nullptr);
      low.push_back(nullptr);
      high.push_back(nullptr);
    } else {
      double sum = 0.0;
      for (double v : values[k]) sum += v;
      mean.push_back(round6(sum / static_cast<double>(values[k].size())));
      low.push_back(round6(quantile(values[k], 0.1)));
      high.push_back(round6(quantile(values[k], 0.9)));
    }
    truth.push_back(density_n[k] > 0 ? json(round6(density_sum[k] / density_n[k])) : json(nullptr));
  }
  return {{"time", time}, {"mean", mean}, {"low", low}, {"high", high}, {"true_density", truth},
          {"agents", agents.size()}, {"bin_width", round6(width)}};
}

}  // namespace

json report_data(const std::string& dir) {
  const auto dirs = run_dirs_of(dir);
  const auto s = scenario::load(dirs.front() + "/scenario.yaml");
  const auto info = run_info(s);
  std::vector<Run> runs;
  json summaries = json::array();
  for (const auto& d : dirs) {
    Run r;
    r.dir = d;
    const auto path = d + "/telemetry.csv";
    r.telemetry = read_table(path);
    r.time = r.telemetry.require("time", path);
    r.inside = r.telemetry.require("inside", path);
    r.deliveries = r.telemetry.require("deliveries", path);
    r.density = r.telemetry.require("true_density", path);
    runs.push_back(std::move(r));
    // A run without a readable summary (still running, or a directory in its place) has none.
    const auto summary = retreat::read_file(d + "/summary.json");
    json j = nullptr;
    if (summary) {
      try {
        j = json::parse(*summary);
      } catch (const json::exception&) {
        j = nullptr;
      }
    }
    summaries.push_back({{"dir", fs::path(d).filename().string()}, {"summary", j}});
  }
  double t_end = 0.0;
  json out;
  out["title"] = s.name;
  out["runs"] = summaries;
  out["lambda_star"] = round6(info.lambda_star);
  out["area"] = round6(info.area);
  out["optimum"] = round6(info.optimal_population());
  out["population"] = population_json(runs, t_end);
  out["duration"] = round6(t_end);
  out["throughput"] = throughput_json(runs, t_end, s, info.area,
                                      static_cast<double>(s.arena.robots_inside + s.arena.robots_waiting));
  out["encounters"] = encounters_json(runs, s);
  out["estimates"] = estimates_json(runs, t_end, s.run.status_period);
  out["model"] = {{"lambda_p", s.model.lambda_p}, {"lambda_d", s.model.lambda_d}, {"C", s.model.C},
                  {"delta", s.model.delta},       {"v", s.model.v},               {"rho", s.model.rho}};
  out["agent"] = {{"L", s.agent.L}, {"K_p", s.agent.K_p}, {"lambda_in", s.agent.lambda_in},
                  {"controller", s.agent.controller}};
  out["arena"] = {{"encounter_model", std::string(retreat::name_of(s.arena.encounter_model))},
                  {"shape", std::string(retreat::name_of(s.arena.shape))},
                  {"robots_inside", s.arena.robots_inside}, {"robots_waiting", s.arena.robots_waiting}};
  return out;
}

std::string render_report(const std::string& dir) {
  const auto data = report_data(dir);
  std::string html;
  html += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  html += "<title>retreat report: " + html_escape(data["title"].get<std::string>()) + "</title>\n";
  html += "<style>\n" + asset_text("vendor/uPlot.min.css") + "\n" + asset_text("report.css") + "\n</style>\n";
  html += "</head>\n<body>\n<main id=\"report\"></main>\n";
  html += "<script>\n" + asset_text("vendor/uPlot.iife.min.js") + "\n</script>\n";
  html += "<script>\nwindow.REPORT = " + script_json(data) + ";\n</script>\n";
  html += "<script>\n" + asset_text("report.js") + "\n</script>\n";
  html += "</body>\n</html>\n";
  return html;
}

std::string write_report(const std::string& dir, const std::string& path) {
  const std::string target = path.empty() ? dir + "/report.html" : path;
  const auto html = render_report(dir);
  const std::string tmp = target + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(target + ": cannot write");
    out << html;
    if (!out) throw std::runtime_error(target + ": cannot write");
  }
  fs::rename(tmp, target);
  return target;
}

}  // namespace retreat::report
