#include "retreat/bridge/live_state.hpp"

#include "retreat/bridge/json.hpp"

namespace retreat::bridge {

void LiveState::update(const std::function<void(telemetry::Aggregator&)>& update) {
  bool moved = false;
  {
    std::lock_guard lock(mutex_);
    const auto before = aggregator_.version();
    update(aggregator_);
    moved = aggregator_.version() != before;
  }
  if (moved) changed_.notify_all();
}

telemetry::Snapshot LiveState::snapshot() const {
  std::lock_guard lock(mutex_);
  return aggregator_.snapshot();
}

std::pair<std::string, std::uint64_t> LiveState::state_text() const {
  std::lock_guard lock(mutex_);
  const auto v = aggregator_.version();
  if (state_cache_version_ != v) {
    state_cache_ = state_json(aggregator_.snapshot()).dump();
    state_cache_version_ = v;
  }
  return {state_cache_, v};
}

std::string LiveState::history_text() const {
  std::lock_guard lock(mutex_);
  const auto v = aggregator_.version();
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
  return aggregator_.version();
}

std::uint64_t LiveState::wait_for_change(std::uint64_t seen, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return closed_ || aggregator_.version() != seen; });
  return aggregator_.version();
}

void LiveState::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool LiveState::closed() const {
  std::lock_guard lock(mutex_);
  return closed_;
}

}  // namespace retreat::bridge
