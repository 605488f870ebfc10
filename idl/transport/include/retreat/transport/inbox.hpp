#pragma once
/// @file
/// The hand-over point between middleware threads and the caller's thread. Vendor threads only
/// push here; everything else (validation, dispatch) happens on the thread that calls take().

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>

#include "retreat/wire/messages.hpp"

namespace retreat::transport {

/// Wakes the caller's thread when any inbox of one transport receives a sample.
class Notifier {
 public:
  void notify();
  /// Blocks until notify() was called after the generation `seen`, or the timeout passes.
  /// Returns the current generation.
  std::uint64_t wait_after(std::uint64_t seen, std::chrono::nanoseconds timeout);
  std::uint64_t generation() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::uint64_t generation_ = 0;
};

/// A bounded FIFO of received samples for one reader. Thread-safe.
class Inbox {
 public:
  /// Holds at most `capacity` samples; beyond that the oldest is dropped and counted.
  explicit Inbox(std::shared_ptr<Notifier> notifier, std::size_t capacity = 1u << 20);

  /// Called from middleware threads: enqueue and wake the caller's thread. Never throws.
  void push(wire::AnyMessage&& sample) noexcept;
  /// Called from middleware threads when the vendor could not decode a sample.
  void count_undecodable() noexcept { undecodable_.fetch_add(1); }

  /// Moves every queued sample into `out` (appending), in arrival order.
  void drain(std::deque<wire::AnyMessage>& out);

  std::uint64_t overflowed() const { return overflowed_.load(); }
  std::uint64_t undecodable() const { return undecodable_.load(); }

 private:
  std::shared_ptr<Notifier> notifier_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::deque<wire::AnyMessage> queue_;
  std::atomic<std::uint64_t> overflowed_{0};
  std::atomic<std::uint64_t> undecodable_{0};
};

}  // namespace retreat::transport
