#include "retreat/telemetry/aggregator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace retreat::telemetry {

namespace {

/// Two simulated times closer than this are the same moment [s].
constexpr double same_time = 1e-9;

}  // namespace

Aggregator::Aggregator(RunInfo run, AggregatorOptions options)
    : run_(std::move(run)), options_(options), spacing_(options.history_spacing) {
  if (options_.histogram_bins == 0) {
    throw std::invalid_argument("telemetry: histogram_bins = 0: must be >= 1");
  }
  if (!(options_.histogram_range_factor > 0.0)) {
    throw std::invalid_argument("telemetry: histogram_range_factor = " +
                                std::to_string(options_.histogram_range_factor) + ": must be > 0");
  }
  if (options_.history_capacity < 4) {
    throw std::invalid_argument("telemetry: history_capacity = " +
                                std::to_string(options_.history_capacity) + ": must be >= 4");
  }
  if (!(options_.history_spacing >= 0.0)) {
    throw std::invalid_argument("telemetry: history_spacing = " +
                                std::to_string(options_.history_spacing) + ": must be >= 0 (s)");
  }
  stale_after_ = options_.stale_after > 0.0 ? options_.stale_after : 3.0 * run_.status_period + 1.0;
}

void Aggregator::reset_run() {
  telemetry_.reset();
  poses_.reset();
  pose_phase_.clear();
  agents_.clear();
  history_.clear();
  spacing_ = options_.history_spacing;
}

void Aggregator::on_telemetry(const wire::ArenaTelemetry& t) {
  ++samples_.telemetry;
  if (telemetry_ && t.time < telemetry_->time - same_time) {
    reset_run();  // the arena's clock went back: a new run on the same topics
  }
  if (!telemetry_) ++runs_;
  telemetry_ = t;
  append_point(t);
  ++version_;
}

void Aggregator::on_poses(const wire::Poses& p) {
  ++samples_.poses;
  if (poses_ && p.tick < poses_->tick) {
    // Older than what we show; unless the run restarted (then telemetry resets us first).
    ++samples_.stale;
    return;
  }
  poses_ = p;
  pose_phase_.clear();
  for (const auto& r : p.robots) pose_phase_[r.robot_id] = r.phase;
  ++version_;
}

void Aggregator::on_status(const wire::AgentStatus& s) {
  ++samples_.statuses;
  const auto it = agents_.find(s.robot_id);
  if (it != agents_.end() && s.tick < it->second.tick) {
    ++samples_.stale;
    return;
  }
  agents_[s.robot_id] = s;
  ++version_;
}

bool Aggregator::counts(const wire::AgentStatus& s) const {
  if (!s.deciding || s.retreating || !std::isfinite(s.lambda_hat)) return false;
  if (telemetry_ && s.time < telemetry_->time - stale_after_) return false;
  if (poses_ && !poses_->robots.empty()) {
    const auto it = pose_phase_.find(s.robot_id);
    if (it == pose_phase_.end() || it->second != wire::Phase::inside) return false;
  }
  return true;
}

EstimateHistogram Aggregator::estimates() const {
  EstimateHistogram h;
  const double range = options_.histogram_range_factor * (run_.lambda_star > 0.0 ? run_.lambda_star : 1.0);
  h.bin_width = range / options_.histogram_bins;
  h.counts.assign(options_.histogram_bins, 0);
  for (const auto& [id, s] : agents_) {
    if (!counts(s)) continue;
    const double v = std::max(0.0, s.lambda_hat);
    const double k = std::floor(v / h.bin_width);
    if (k >= static_cast<double>(options_.histogram_bins)) {
      ++h.overflow;
    } else {
      ++h.counts[static_cast<std::size_t>(k)];
    }
    ++h.count;
    h.sum += v;
    h.min = h.count == 1 ? v : std::min(h.min, v);
    h.max = h.count == 1 ? v : std::max(h.max, v);
  }
  return h;
}

void Aggregator::append_point(const wire::ArenaTelemetry& t) {
  HistoryPoint p;
  p.time = t.time;
  p.tick = t.tick;
  p.inside = t.inside;
  p.waiting = t.waiting;
  p.retreating = t.retreating;
  p.departed = t.departed;
  p.lost_agents = t.lost_agents;
  p.deliveries = t.deliveries;
  p.true_density = t.true_density;
  p.ticks_per_second = t.ticks_per_second;
  const auto h = estimates();
  p.estimates = h.count;
  p.lambda_hat_mean = h.mean();
  p.lambda_hat_min = h.min;
  p.lambda_hat_max = h.max;

  if (!history_.empty()) {
    const double gap = t.time - history_.back().time;
    if (gap <= same_time) {
      history_.back() = p;  // the same moment again (e.g. the arena's final publication)
      return;
    }
    if (gap < spacing_ * (1.0 - 1e-6) - same_time) return;
  }
  history_.push_back(p);
  if (history_.size() <= options_.history_capacity) return;

  // Full: keep every second point (the oldest and the newest always), double the spacing.
  const double span = history_.back().time - history_.front().time;
  const double mean_gap = span / static_cast<double>(history_.size() - 1);
  std::deque<HistoryPoint> kept;
  for (std::size_t i = 0; i < history_.size(); i += 2) kept.push_back(history_[i]);
  if ((history_.size() - 1) % 2 != 0) kept.push_back(history_.back());
  history_ = std::move(kept);
  spacing_ = 2.0 * std::max(spacing_, mean_gap);
  ++compactions_;
}

Snapshot Aggregator::snapshot() const {
  Snapshot s;
  s.run = run_;
  s.telemetry = telemetry_;
  s.poses = poses_;
  s.agents.reserve(agents_.size());
  for (const auto& [id, status] : agents_) s.agents.push_back({status, counts(status)});
  s.estimates = estimates();
  s.samples = samples_;
  s.history_size = history_.size();
  s.history_spacing = spacing_;
  s.history_compactions = compactions_;
  if (!history_.empty()) s.last_point = history_.back();
  s.runs = runs_;
  s.version = version_;
  return s;
}

}  // namespace retreat::telemetry
