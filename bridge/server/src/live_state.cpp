#include "retreat/bridge/live_state.hpp"

#include "retreat/bridge/json.hpp"

namespace retreat::bridge {

void LiveState::update(const std::function<void(telemetry::Aggregator&)>& update) {
  std::lock_guard lock(mutex_);
  update(aggregator_);
  // Every update moves our version on, also one that put in a new aggregator (a replay seeking
  // back), whose own count starts again and may even come back to the old count.
  ++version_;
}

telemetry::Snapshot LiveState::snapshot() const {
  std::lock_guard lock(mutex_);
  return aggregator_.snapshot();
}

std::pair<std::string, std::uint64_t> LiveState::state_text() const {
  std::lock_guard lock(mutex_);
  const auto v = version_;
  if (state_cache_version_ != v) {
    state_cache_ = state_json(aggregator_.snapshot()).dump();
    state_cache_version_ = v;
  }
  return {state_cache_, v};
}

std::string LiveState::history_text() const {
  std::lock_guard lock(mutex_);
  const auto v = version_;
  if (history_cache_version_ != v) {
    const auto s = aggregator_.snapshot();
    history_cache_ = history_json(aggregator_.history(), s.history_spacing, s.history_compactions).dump();
    history_cache_version_ = v;
  }
  return history_cache_;
}

std::string LiveState::metrics_text(const std::function<void(telemetry::PrometheusWriter&)>& extra) const {
  telemetry::PrometheusWriter out;
  telemetry::write_swarm_metrics(out, snapshot());
  if (extra) extra(out);
  return out.text();
}

std::uint64_t LiveState::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

}  // namespace retreat::bridge
