#pragma once
/// @file
/// QoS intents: what a topic needs, stated once and mapped by every implementation.

#include <cstdint>
#include <string>

namespace retreat::transport {

enum class Reliability { reliable, best_effort };
enum class Durability { volatile_data, transient_local };

/// What an endpoint needs from the middleware. `depth == 0` means keep all samples (with
/// reliability: none lost, the writer blocks when the reader falls behind); otherwise keep the
/// last `depth` samples per instance (key).
struct QosIntent {
  Reliability reliability = Reliability::reliable;
  Durability durability = Durability::volatile_data;
  std::uint32_t depth = 0;

  /// Reliable, volatile, keep all: per-robot proximity frames and decisions (lockstep relies on
  /// every sample arriving, in order).
  static constexpr QosIntent control() { return {Reliability::reliable, Durability::volatile_data, 0}; }
  /// Reliable, transient-local, keep last 1 per instance: status, telemetry, poses; a late joiner
  /// receives the newest sample of every instance.
  static constexpr QosIntent state() { return {Reliability::reliable, Durability::transient_local, 1}; }
  bool operator==(const QosIntent&) const = default;
};

/// A topic: its full name (see retreat/wire/topics.hpp) and the QoS intent of this endpoint.
struct TopicSpec {
  std::string name;
  QosIntent qos;
};

}  // namespace retreat::transport
