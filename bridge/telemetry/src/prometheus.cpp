#include "retreat/telemetry/prometheus.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace retreat::telemetry {

namespace {

bool name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool name_char(char c) { return name_start(c) || (c >= '0' && c <= '9'); }

}  // namespace

bool PrometheusWriter::is_metric_name(std::string_view name) {
  if (name.empty() || !(name_start(name[0]) || name[0] == ':')) return false;
  for (char c : name) {
    if (!name_char(c) && c != ':') return false;
  }
  return true;
}

bool PrometheusWriter::is_label_name(std::string_view name) {
  if (name.empty() || !name_start(name[0])) return false;
  for (char c : name) {
    if (!name_char(c)) return false;
  }
  return true;
}

std::string PrometheusWriter::format_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  char buffer[64];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (error != std::errc()) throw std::logic_error("prometheus: cannot format a value");
  return std::string(buffer, end);
}

std::string PrometheusWriter::escape_label_value(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (char c : value) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '"') {
      out += "\\\"";
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

void PrometheusWriter::family(std::string_view name, std::string_view type, std::string_view help) {
  if (!is_metric_name(name)) throw std::invalid_argument("prometheus: bad metric name '" + std::string(name) + "'");
  if (type != "counter" && type != "gauge" && type != "histogram" && type != "summary" && type != "untyped") {
    throw std::invalid_argument("prometheus: bad metric type '" + std::string(type) + "'");
  }
  if (!seen_.insert(std::string(name)).second) {
    throw std::invalid_argument("prometheus: family '" + std::string(name) + "' written twice");
  }
  current_ = name;
  // HELP text: backslash and newline escaped.
  std::string escaped;
  for (char c : help) {
    if (c == '\\') {
      escaped += "\\\\";
    } else if (c == '\n') {
      escaped += "\\n";
    } else {
      escaped += c;
    }
  }
  text_ += "# HELP " + current_ + " " + escaped + "\n";
  text_ += "# TYPE " + current_ + " " + std::string(type) + "\n";
}

void PrometheusWriter::sample(double value, const Labels& labels, std::string_view suffix) {
  if (current_.empty()) throw std::logic_error("prometheus: sample() before family()");
  text_ += current_;
  text_ += suffix;
  if (!labels.empty()) {
    text_ += '{';
    bool first = true;
    for (const auto& [key, v] : labels) {
      if (!is_label_name(key)) throw std::invalid_argument("prometheus: bad label name '" + key + "'");
      if (!first) text_ += ',';
      first = false;
      text_ += key + "=\"" + escape_label_value(v) + "\"";
    }
    text_ += '}';
  }
  text_ += ' ';
  text_ += format_value(value);
  text_ += '\n';
}

void PrometheusWriter::histogram(const std::vector<double>& upper_bounds,
                                 const std::vector<std::uint32_t>& counts, std::uint64_t overflow,
                                 double sum, const Labels& labels) {
  if (upper_bounds.size() != counts.size()) throw std::logic_error("prometheus: bounds and counts differ in size");
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    cumulative += counts[i];
    Labels l = labels;
    l.emplace_back("le", format_value(upper_bounds[i]));
    sample(static_cast<double>(cumulative), l, "_bucket");
  }
  cumulative += overflow;
  Labels inf = labels;
  inf.emplace_back("le", "+Inf");
  sample(static_cast<double>(cumulative), inf, "_bucket");
  sample(sum, labels, "_sum");
  sample(static_cast<double>(cumulative), labels, "_count");
}

void write_swarm_metrics(PrometheusWriter& out, const Snapshot& s) {
  const auto d = [](auto v) { return static_cast<double>(v); };
  out.family("retreat_optimal_density", "gauge", "Optimal robot density lambda* [robots/m^2].");
  out.sample(s.run.lambda_star);
  out.family("retreat_optimal_population", "gauge", "Optimal population lambda* |D| [robots].");
  out.sample(s.run.optimal_population());
  out.family("retreat_domain_area", "gauge", "Area of the domain |D| [m^2].");
  out.sample(s.run.area);
  out.family("retreat_runs", "gauge", "Runs seen by this bridge (a clock going back starts a new one).");
  out.sample(d(s.runs));

  if (s.telemetry) {
    const auto& t = *s.telemetry;
    out.family("retreat_robots", "gauge", "Robots by phase (arena ground truth).");
    out.sample(d(t.waiting), {{"phase", "waiting"}});
    out.sample(d(t.inside), {{"phase", "inside"}});
    out.sample(d(t.retreating), {{"phase", "retreating"}});
    out.sample(d(t.departed), {{"phase", "departed"}});
    out.family("retreat_lost_agents", "gauge", "Agents the arena declared lost.");
    out.sample(d(t.lost_agents));
    out.family("retreat_deliveries_total", "counter", "Deliveries since the run started.");
    out.sample(d(t.deliveries));
    out.family("retreat_arena_tick", "gauge", "The arena's newest tick.");
    out.sample(d(t.tick));
    out.family("retreat_arena_time_seconds", "gauge", "The arena's simulated clock [s].");
    out.sample(t.time);
    out.family("retreat_arena_ticks_per_second", "gauge", "Wall-clock rate of the arena loop [ticks/s].");
    out.sample(t.ticks_per_second);
    out.family("retreat_true_density", "gauge", "Robots inside per |D| [robots/m^2].");
    out.sample(t.true_density);
  }
  if (s.poses) {
    std::uint32_t loaded = 0;
    for (const auto& r : s.poses->robots) loaded += r.loaded ? 1 : 0;
    out.family("retreat_robots_loaded", "gauge", "Robots in D carrying an item.");
    out.sample(d(loaded));
  }

  out.family("retreat_agents_reporting", "gauge", "Agents heard from (status received).");
  out.sample(d(s.agents.size()));
  if (!s.agents.empty()) {
    out.family("retreat_agent_lambda_hat", "gauge", "Each agent's density estimate [robots/m^2].");
    for (const auto& a : s.agents) out.sample(a.status.lambda_hat, {{"robot", std::to_string(a.status.robot_id)}});
    out.family("retreat_agent_epsilon", "gauge", "Each agent's retreat rate epsilon [1/s].");
    for (const auto& a : s.agents) out.sample(a.status.epsilon, {{"robot", std::to_string(a.status.robot_id)}});
    out.family("retreat_agent_onsets_in_window", "gauge", "Encounter onsets in each agent's window L.");
    for (const auto& a : s.agents) {
      out.sample(d(a.status.onsets_in_window), {{"robot", std::to_string(a.status.robot_id)}});
    }
    out.family("retreat_agent_deciding", "gauge", "1 if the agent is deciding (inside for L, not retreating).");
    for (const auto& a : s.agents) out.sample(a.status.deciding ? 1.0 : 0.0, {{"robot", std::to_string(a.status.robot_id)}});
    out.family("retreat_agent_frames_dropped_total", "counter", "Invalid proximity frames each agent dropped.");
    for (const auto& a : s.agents) {
      out.sample(d(a.status.frames_dropped), {{"robot", std::to_string(a.status.robot_id)}});
    }
  }

  const auto& h = s.estimates;
  std::vector<double> bounds;
  for (std::size_t k = 0; k < h.counts.size(); ++k) bounds.push_back(h.bin_width * d(k + 1));
  out.family("retreat_lambda_hat", "histogram",
             "Current estimates of the deciding agents whose robot is inside [robots/m^2].");
  out.histogram(bounds, h.counts, h.overflow, h.sum);

  out.family("retreat_bridge_samples_total", "counter", "Samples the bridge received, by topic.");
  out.sample(d(s.samples.telemetry), {{"topic", "arena_telemetry"}});
  out.sample(d(s.samples.poses), {{"topic", "poses"}});
  out.sample(d(s.samples.statuses), {{"topic", "agent_status"}});
  out.family("retreat_bridge_samples_stale_total", "counter", "Samples ignored as older than what was known.");
  out.sample(d(s.samples.stale));
}

}  // namespace retreat::telemetry
