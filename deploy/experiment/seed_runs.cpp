#include "seed_runs.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>

#include "retreat/core/paths.hpp"
#include "retreat/experiment/common.hpp"

namespace retreat::experiment {
namespace {

namespace fs = std::filesystem;

/// The columns of telemetry.csv the experiments use, one entry per tick.
struct Telemetry {
  std::vector<double> time, inside, retreating, departed, deliveries;
};

/// The next line of @p text from @p at (without its '\n'); @p at moves past it.
std::string_view next_line(std::string_view text, std::size_t& at) {
  const std::size_t end = std::min(text.find('\n', at), text.size());
  const std::string_view line = text.substr(at, end - at);
  at = end + 1;
  return line;
}

/// The five columns the experiments use; only their cells are parsed, and every row must have
/// the header's length. The file is read with retreat::read_file: a directory or anything else
/// that is not a file is named in one line (an std::ifstream opens a directory and throws on
/// its first read, naming nothing).
Telemetry read_telemetry(const std::string& path) {
  const auto bytes = retreat::read_file(path);
  if (!bytes) throw RunFailure("'" + path + "': missing, or not a file (the launcher wrote no telemetry)");
  const std::string_view text = *bytes;
  std::size_t at = 0;
  std::vector<std::string_view> header;
  {
    const std::string_view line = next_line(text, at);
    for (std::size_t from = 0; from <= line.size();) {
      const std::size_t comma = std::min(line.find(',', from), line.size());
      header.push_back(line.substr(from, comma - from));
      from = comma + 1;
    }
  }
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw RunFailure("'" + path + "': no column '" + name + "'");
    return static_cast<std::size_t>(it - header.begin());
  };
  Telemetry t;
  std::vector<std::vector<double>*> into(header.size(), nullptr);  // by column; null: not used
  into[column("time")] = &t.time;
  into[column("inside")] = &t.inside;
  into[column("retreating")] = &t.retreating;
  into[column("departed")] = &t.departed;
  into[column("deliveries")] = &t.deliveries;
  while (at < text.size()) {
    const std::string_view line = next_line(text, at);
    const char* p = line.data();
    const char* const last = p + line.size();
    std::size_t cells = 0;
    for (;;) {
      const char* const comma = std::find(p, last, ',');
      if (cells == into.size()) throw RunFailure("'" + path + "': a row longer than the header: " + std::string(line));
      if (auto* const values = into[cells]) {
        // std::from_chars: the same correctly rounded doubles as strtod, without its locale.
        double cell = 0.0;
        const auto [end, ec] = std::from_chars(p, comma, cell);
        if (ec != std::errc() || end != comma) {
          throw RunFailure("'" + path + "': a cell that is not a number: " + std::string(line));
        }
        values->push_back(cell);
      }
      ++cells;
      if (comma == last) break;
      p = comma + 1;
    }
    if (cells != into.size()) throw RunFailure("'" + path + "': a short row: " + std::string(line));
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
  // A summary that does not parse, or lacks a field or has one of another type, is named.
  const auto bad_summary = [&](const nlohmann::json::exception& e) {
    return RunFailure("'" + summary_path + "': " + e.what());
  };
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(*summary_text);
    r.area = summary.at("area").get<double>();
    r.optimal_population = summary.at("optimal_population").get<double>();
    r.agents_lost = summary.at("agents").value("lost", 0u);
    r.trajectory_sha256 = summary.value("trajectory_sha256", std::string());
    r.longest_retreat_under_way =
        summary.value(nlohmann::json::json_pointer("/retreats/longest_under_way_seconds"), 0.0);
  } catch (const nlohmann::json::exception& e) {
    throw bad_summary(e);
  }
  auto t = read_telemetry((d / "telemetry.csv").string());
  try {
    pad_emptied_run(t, summary);
  } catch (const nlohmann::json::exception& e) {
    throw bad_summary(e);
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
