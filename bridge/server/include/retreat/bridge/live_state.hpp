#pragma once
/// @file
/// The aggregator behind a mutex: the receiving thread updates it, the HTTP threads read it.
/// Renderings (state JSON, history JSON, metrics) are cached per version, so that many readers
/// of an unchanged state cost one rendering.

#include <chrono>
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

  /// Runs `update` on the aggregator under the lock; the version moves on.
  void update(const std::function<void(telemetry::Aggregator&)>& update);

  telemetry::Snapshot snapshot() const;
  /// The state as JSON text and its version.
  std::pair<std::string, std::uint64_t> state_text() const;
  /// The time series as JSON text.
  std::string history_text() const;
  /// Prometheus text of the swarm, followed by `extra` (the server's own families).
  std::string metrics_text(const std::function<void(telemetry::PrometheusWriter&)>& extra = {}) const;
  /// Moves on with every update(), never back (unlike the aggregator's own count, which starts
  /// again when a replay seeking back puts in a new aggregator).
  std::uint64_t version() const;

 private:
  mutable std::mutex mutex_;
  telemetry::Aggregator aggregator_;
  std::uint64_t version_ = 0;
  mutable std::uint64_t state_cache_version_ = ~std::uint64_t{0};
  mutable std::string state_cache_;
  mutable std::uint64_t history_cache_version_ = ~std::uint64_t{0};
  mutable std::string history_cache_;
};

}  // namespace retreat::bridge
