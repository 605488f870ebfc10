#pragma once
/// @file
/// Prometheus text exposition format (version 0.0.4): a small writer that keeps every family
/// together under its HELP and TYPE lines, and the rendering of a Snapshot.

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "retreat/telemetry/aggregator.hpp"

namespace retreat::telemetry {

/// Content-Type of the text format.
inline constexpr const char* prometheus_content_type = "text/plain; version=0.0.4; charset=utf-8";

using Labels = std::vector<std::pair<std::string, std::string>>;

/// Writes metric families one after the other. Names must match [a-zA-Z_:][a-zA-Z0-9_:]*,
/// label names [a-zA-Z_][a-zA-Z0-9_]*; label values are escaped (\\, \", \n).
class PrometheusWriter {
 public:
  /// Starts a family: `# HELP name help` and `# TYPE name type` (type: counter, gauge,
  /// histogram, summary or untyped). @throws std::invalid_argument for a bad or repeated name.
  void family(std::string_view name, std::string_view type, std::string_view help);
  /// One sample of the current family; `suffix` is appended to the family name (histograms:
  /// `_bucket`, `_sum`, `_count`). @throws std::logic_error before any family().
  void sample(double value, const Labels& labels = {}, std::string_view suffix = {});
  /// A histogram from bucket upper bounds and per-bucket (non-cumulative) counts; `overflow`
  /// is the count above the last bound. Writes cumulative `_bucket{le=...}` lines, `+Inf`,
  /// `_sum` and `_count`.
  void histogram(const std::vector<double>& upper_bounds, const std::vector<std::uint32_t>& counts,
                 std::uint64_t overflow, double sum, const Labels& labels = {});

  const std::string& text() const { return text_; }

  /// A float as the format wants it: shortest round-trip decimal, `NaN`, `+Inf`, `-Inf`.
  static std::string format_value(double value);
  /// A label value with \\, \" and newline escaped.
  static std::string escape_label_value(std::string_view value);
  static bool is_metric_name(std::string_view name);
  static bool is_label_name(std::string_view name);

 private:
  std::string text_;
  std::string current_;
  std::set<std::string, std::less<>> seen_;
};

/// The swarm's metrics, all prefixed `retreat_`: robots by phase, lost agents, deliveries, tick,
/// simulated time, ticks per second, true and optimal density and population, each agent's
/// estimate, ε and window count (label `robot`), the estimate histogram, and sample counters.
void write_swarm_metrics(PrometheusWriter& out, const Snapshot& snapshot);

}  // namespace retreat::telemetry
