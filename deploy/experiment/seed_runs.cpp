#include "seed_runs.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "retreat/core/paths.hpp"
#include "retreat/experiment/common.hpp"

namespace retreat::experiment {
namespace {

namespace fs = std::filesystem;

/// The columns of telemetry.csv the experiments use, one entry per tick.
struct Telemetry {
  std::vector<double> time, inside, retreating, departed, deliveries;
};

Telemetry read_telemetry(const std::string& path) {
  // retreat::read_file: a directory in the file's place is named here, where an std::ifstream's
  // first read would throw a stream error that names nothing.
  auto bytes = retreat::read_file(path);
  if (!bytes) throw RunFailure("'" + path + "': missing, or not a file (the launcher wrote no telemetry)");
  std::istringstream in(std::move(*bytes));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::istringstream h(line);
    for (std::string cell; std::getline(h, cell, ',');) header.push_back(cell);
  }
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw RunFailure("'" + path + "': no column '" + name + "'");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t time = column("time"), inside = column("inside"), retreating = column("retreating"),
                    departed = column("departed"), deliveries = column("deliveries");
  Telemetry t;
  std::vector<double> row;
  while (std::getline(in, line)) {
    row.clear();
    // std::from_chars: the same correctly rounded doubles as strtod, without its locale.
    const char* p = line.data();
    const char* const last = p + line.size();
    while (p != last) {
      double cell = 0.0;
      const auto [end, ec] = std::from_chars(p, last, cell);
      if (ec != std::errc() || end == p) throw RunFailure("'" + path + "': a cell that is not a number: " + line);
      row.push_back(cell);
      p = end != last && *end == ',' ? end + 1 : end;
    }
    if (row.size() != header.size()) throw RunFailure("'" + path + "': a short row: " + line);
    t.time.push_back(row[time]);
    t.inside.push_back(row[inside]);
    t.retreating.push_back(row[retreating]);
    t.departed.push_back(row[departed]);
    t.deliveries.push_back(row[deliveries]);
  }
  if (t.time.size() < 2) throw RunFailure("'" + path + "': fewer than two ticks");
  return t;
}

/// Rows are ticks at equal spacing, so the time-mean over a span is the mean of its rows; the
/// deliveries of the span are the counter's increase from the last row before it.
SpanCost span_cost(const Telemetry& t, double from, double to, double area, double C) {
  SpanCost s;
  s.from = from;
  s.to = to;
  double sum = 0.0;
  std::size_t n = 0;
  double delivered_before = 0.0;  // the counter at `from` (0 at t = 0)
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    if (t.time[k] <= from + 1e-9) {
      delivered_before = t.deliveries[k];
      continue;
    }
    if (t.time[k] > to + 1e-9) break;
    sum += t.inside[k];
    ++n;
  }
  s.mean_population = n > 0 ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
  s.deliveries = t.deliveries.back() - delivered_before;
  s.lambda = s.mean_population / area;
  s.output = s.deliveries / (area * (to - from));
  s.J = s.output > 0.0 ? C / s.output + s.lambda : std::numeric_limits<double>::infinity();
  return s;
}

/// A swarm that emptied ends its run early (summary.json's `population.emptied_at`) and would
/// stay empty: the ticks up to `run_duration` are added with nobody inside and no deliveries, so
/// every span is measured against the run's configured length, not against a crowded start.
void pad_emptied_run(Telemetry& t, const nlohmann::json& summary) {
  const auto emptied = summary.find("population");
  if (emptied == summary.end() || !emptied->contains("emptied_at") || emptied->at("emptied_at").is_null()) return;
  const double duration = summary.value("run_duration", 0.0);
  const double dt = t.time[1] - t.time[0];
  const double end = t.time.back();
  const auto missing = static_cast<std::size_t>(std::llround((duration - end) / dt));
  for (std::size_t k = 1; k <= missing; ++k) {
    t.time.push_back(end + dt * static_cast<double>(k));
    t.inside.push_back(0.0);
    t.retreating.push_back(0.0);
    t.departed.push_back(t.departed.back());
    t.deliveries.push_back(t.deliveries.back());
  }
}

std::uint64_t seed_of(const fs::path& p) { return std::strtoull(p.filename().string().c_str() + 5, nullptr, 10); }

SeedRun read_seed_run(const fs::path& d, double C, double grid_step) {
  SeedRun r;
  r.seed = seed_of(d);
  r.dir = d.string();
  const std::string summary_path = (d / "summary.json").string();
  const auto summary_text = retreat::read_file(summary_path);
  if (!summary_text) throw RunFailure("'" + summary_path + "': missing, or not a file (the launcher wrote no summary)");
  Telemetry t;
  // Only the summary throws JSON exceptions here: one that does not parse, or lacks a field or
  // has one of another type, is named (read_telemetry names its own file).
  try {
    const auto summary = nlohmann::json::parse(*summary_text);
    r.area = summary.at("area").get<double>();
    r.optimal_population = summary.at("optimal_population").get<double>();
    r.agents_lost = summary.at("agents").value("lost", 0u);
    r.trajectory_sha256 = summary.value("trajectory_sha256", std::string());
    r.longest_retreat_under_way =
        summary.value(nlohmann::json::json_pointer("/retreats/longest_under_way_seconds"), 0.0);
    t = read_telemetry((d / "telemetry.csv").string());
    pad_emptied_run(t, summary);
  } catch (const nlohmann::json::exception& e) {
    throw RunFailure("'" + summary_path + "': " + e.what());
  }
  r.duration = t.time.back();
  r.final_population = t.inside.back();
  r.departed = t.departed.back();
  r.retreating_at_end = t.retreating.back();
  r.whole = span_cost(t, 0.0, r.duration, r.area, C);
  r.last_half = span_cost(t, r.duration / 2.0, r.duration, r.area, C);
  r.mean_last_300s = span_cost(t, std::max(0.0, r.duration - 300.0), r.duration, r.area, C).mean_population;
  std::size_t k = 0;
  const auto steps = static_cast<std::size_t>(std::floor(r.duration / grid_step + 1e-9));
  for (std::size_t i = 0; i <= steps; ++i) {
    const double at = grid_step * static_cast<double>(i);
    while (k + 1 < t.time.size() && t.time[k + 1] <= at + 1e-9) ++k;
    // Before the first tick the population is the first tick's (robots_inside at t = 0).
    r.population.push_back(t.inside[k]);
  }
  return r;
}

}  // namespace

std::vector<SeedRun> read_seed_runs(const std::string& launch_out, double C, double grid_step, unsigned jobs) {
  std::vector<fs::path> dirs;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(launch_out, ec)) {
    if (e.is_directory() && e.path().filename().string().rfind("seed_", 0) == 0) dirs.push_back(e.path());
  }
  if (dirs.empty()) throw RunFailure("'" + launch_out + "': no seed_<n> run directories");
  std::sort(dirs.begin(), dirs.end(), [](const auto& a, const auto& b) { return seed_of(a) < seed_of(b); });
  // Each seed's directory is read on its own: the same runs, in seed order, whatever `jobs` is.
  std::vector<SeedRun> runs(dirs.size());
  for_each_index(dirs.size(), jobs, [&](std::size_t i) { runs[i] = read_seed_run(dirs[i], C, grid_step); });
  return runs;
}

}  // namespace retreat::experiment
