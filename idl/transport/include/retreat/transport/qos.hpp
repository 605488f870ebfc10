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
  /// Reliable, volatile, keep last `answers_depth`: an agent's decision writer. A reader that
  /// stops acknowledging (an arena killed by a signal, matched until its participant lease
  /// expires: Fast DDS 20 s, Cyclone DDS 10 s) then holds at most that many samples and can never
  /// block the writer, whatever vendor; a keep-all writer blocks once its history (Fast DDS) or
  /// its unacknowledged bytes (Cyclone DDS) are full. A live reader loses nothing: lockstep has
  /// at most a few answers in flight. History is not a request/offered QoS: readers still ask
  /// control(), and the wire does not change (docs/protocol.md §6).
  static constexpr QosIntent answers() {
    return {Reliability::reliable, Durability::volatile_data, answers_depth};
  }
  /// 64 decisions: well under Cyclone DDS's initial writer high-water mark (30 kB at ~110 bytes
  /// a decision), above which a writer throttles until a dead reader acknowledges.
  static constexpr std::uint32_t answers_depth = 64;
  /// Reliable, transient-local, keep last 1 per instance: status, telemetry, poses; a late joiner
  /// receives the newest sample of every instance.
  static constexpr QosIntent state() { return {Reliability::reliable, Durability::transient_local, 1}; }
  /// Best effort, volatile, keep last 1: a reader that wants only the newest sample and sends
  /// no acknowledgements (retreat-launch's progress line; a lost sample is made good by the next,
  /// whose counts are totals). It matches a state() writer.
  static constexpr QosIntent newest() { return {Reliability::best_effort, Durability::volatile_data, 1}; }
  /// This intent for a writer whose every sample @p recorders recorders must get (run.recorders):
  /// a keep-last writer then keeps the last `recorded_depth` per instance, so that a sample is not
  /// replaced before a recorder that keeps up has acknowledged it (keep-last-1 was seen to lose
  /// 0.5 % of the telemetry to a Fast DDS recorder), and is transient-local, so that a recorder
  /// whose reader matches it only after its first samples (the writer's side of a match can come
  /// first, e.g. a Fast DDS agent and a Cyclone DDS recorder) still gets them: the recorder asks
  /// for them with a transient-local reader (recorder/recorder.hpp). Readers of the swarm stay
  /// volatile, get only new samples, and match either way (a volatile reader matches a
  /// transient-local writer); a late joiner of state() gets up to that many samples per instance
  /// instead of one, and a dead reader of answers() may hold more of them (Cyclone DDS throttles a
  /// writer above its high-water mark until the reader's lease ends). Unchanged without
  /// recorders, and for keep-all.
  constexpr QosIntent kept_for_recorders(std::uint32_t recorders) const {
    QosIntent kept = *this;
    if (recorders > 0 && depth != 0) {
      kept.depth = depth < recorded_depth ? recorded_depth : depth;
      kept.durability = Durability::transient_local;
    }
    return kept;
  }
  static constexpr std::uint32_t recorded_depth = 1024;
  bool operator==(const QosIntent&) const = default;
};

/// A topic: its full name (see retreat/wire/topics.hpp) and the QoS intent of this endpoint.
struct TopicSpec {
  std::string name;
  QosIntent qos;
};

}  // namespace retreat::transport
