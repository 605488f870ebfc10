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
#include <vector>

#include "retreat/wire/messages.hpp"

namespace retreat::transport {

/// Whether the samples of a transport are pushed from other threads (middleware threads, or
/// other threads' writers on a shared in-memory bus) or only from the thread that takes them.
enum class Threading {
  shared,    ///< pushes from any thread: inboxes lock, waits block
  confined,  ///< one thread does everything: no locks, and a wait returns at once (nobody else
             ///< could push while it waits)
};

/// Wakes the caller's thread when any inbox of one transport receives a sample.
class Notifier {
 public:
  explicit Notifier(Threading threading = Threading::shared) : threading_(threading) {}
  void notify();
  /// Blocks until notify() was called after the generation `seen`, or the timeout passes
  /// (confined: returns at once). Returns the current generation.
  std::uint64_t wait_after(std::uint64_t seen, std::chrono::nanoseconds timeout);
  std::uint64_t generation() const;
  Threading threading() const { return threading_; }

 private:
  Threading threading_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::uint64_t generation_ = 0;
};

/// A bounded FIFO of received samples for one reader. Thread-safe unless its notifier is
/// Threading::confined.
class Inbox {
 public:
  /// Holds at most `capacity` samples; beyond that the oldest is dropped and counted.
  explicit Inbox(std::shared_ptr<Notifier> notifier, std::size_t capacity = 1u << 20);

  /// Called from middleware threads: enqueue and wake the caller's thread. Never throws.
  void push(wire::AnyMessage&& sample) noexcept;
  /// Called from middleware threads when the vendor could not decode a sample.
  void count_undecodable() noexcept { undecodable_.fetch_add(1); }

  /// Calls @p take(sample) for every queued sample, in arrival order, and empties the inbox.
  /// @p take runs under the inbox's lock (shared): it must not touch this inbox.
  template <class Take>
  void drain(Take&& take) {
    const auto held = lock();
    if (has_first_) {
      has_first_ = false;
      take(std::move(first_));
    }
    for (auto& sample : rest_) take(std::move(sample));
    rest_.clear();
    size_.store(0, std::memory_order_relaxed);
  }
  /// Nothing is queued (a hint only, when other threads push).
  bool empty() const { return size_.load(std::memory_order_relaxed) == 0; }

  std::uint64_t overflowed() const { return overflowed_.load(); }
  std::uint64_t undecodable() const { return undecodable_.load(); }

 private:
  /// The inbox's lock, held; none when confined.
  std::unique_lock<std::mutex> lock() {
    return confined_ ? std::unique_lock<std::mutex>() : std::unique_lock<std::mutex>(mutex_);
  }

  std::shared_ptr<Notifier> notifier_;
  std::size_t capacity_;
  bool confined_;
  std::mutex mutex_;
  // The queue is first_ (while has_first_) then rest_. A sample that arrives to an empty inbox
  // goes to first_, inside this object: the usual one sample per reader per tick costs no
  // allocation and no memory beyond the inbox itself.
  bool has_first_ = false;
  wire::AnyMessage first_;
  std::deque<wire::AnyMessage> rest_;
  std::atomic<std::size_t> size_{0};
  std::atomic<std::uint64_t> overflowed_{0};
  std::atomic<std::uint64_t> undecodable_{0};
};

/// One sample as it travelled, for recorders: its serialized bytes (the 4-byte encapsulation
/// header, then the XCDR1 body) and the writer's source timestamp.
struct RawSample {
  std::vector<std::uint8_t> cdr;
  std::int64_t source_time_ns = 0;  ///< the writer's source timestamp [ns since the Unix epoch]
};

/// A bounded FIFO of raw samples for one raw reader (always pushed from middleware threads).
class RawInbox {
 public:
  /// Holds at most `capacity` samples; beyond that the oldest is dropped and counted.
  explicit RawInbox(std::shared_ptr<Notifier> notifier, std::size_t capacity = 1u << 20);
  /// Called from middleware threads: enqueue and wake the caller's thread. Never throws.
  void push(RawSample&& sample) noexcept;
  /// Appends every queued sample to @p out, in arrival order, and empties the inbox.
  void drain_into(std::vector<RawSample>& out);
  /// Counts a sample lost before it could be queued (e.g. it could not be serialized).
  void count_lost() noexcept { overflowed_.fetch_add(1); }
  /// Samples dropped: beyond the capacity, or counted lost.
  std::uint64_t overflowed() const { return overflowed_.load(); }

 private:
  std::shared_ptr<Notifier> notifier_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::deque<RawSample> queue_;
  std::atomic<std::uint64_t> overflowed_{0};
};

}  // namespace retreat::transport
