#pragma once
/// @file
/// The aggregator behind a mutex: the receiving thread updates it, the HTTP threads read it.
/// Renderings (state JSON, history JSON, metrics) are cached per version, so that many readers
/// of an unchanged state cost one rendering.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>

#include "retreat/telemetry/aggregator.hpp"
#include "retreat/telemetry/prometheus.hpp"

namespace retreat::bridge {

class LiveState {
 public:
  explicit LiveState(telemetry::Aggregator aggregator) : aggregator_(std::move(aggregator)) {}

  /// Runs `update` on the aggregator under the lock and wakes every waiter if the version moved.
  void update(const std::function<void(telemetry::Aggregator&)>& update);

  telemetry::Snapshot snapshot() const;
  /// The state as JSON text and its version.
  std::pair<std::string, std::uint64_t> state_text() const;
  /// The time series as JSON text.
  std::string history_text() const;
  /// Prometheus text of the swarm, followed by `extra` (the server's own families).
  std::string metrics_text(const std::function<void(telemetry::PrometheusWriter&)>& extra = {}) const;
  std::uint64_t version() const;

  /// Blocks until the version differs from `seen`, `close()` was called, or the timeout passes.
  /// Returns the current version.
  std::uint64_t wait_for_change(std::uint64_t seen, std::chrono::milliseconds timeout) const;
  /// Wakes every waiter for good (shutdown).
  void close();
  bool closed() const;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  telemetry::Aggregator aggregator_;
  bool closed_ = false;
  mutable std::uint64_t state_cache_version_ = ~std::uint64_t{0};
  mutable std::string state_cache_;
  mutable std::uint64_t history_cache_version_ = ~std::uint64_t{0};
  mutable std::string history_cache_;
};

}  // namespace retreat::bridge
