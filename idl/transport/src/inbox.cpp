#include "retreat/transport/inbox.hpp"

namespace retreat::transport {

void Notifier::notify() {
  if (threading_ == Threading::confined) {
    ++generation_;
    return;
  }
  {
    std::lock_guard lock(mutex_);
    ++generation_;
  }
  changed_.notify_all();
}

std::uint64_t Notifier::wait_after(std::uint64_t seen, std::chrono::nanoseconds timeout) {
  if (threading_ == Threading::confined) return generation_;
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return generation_ != seen; });
  return generation_;
}

std::uint64_t Notifier::generation() const {
  if (threading_ == Threading::confined) return generation_;
  std::lock_guard lock(mutex_);
  return generation_;
}

Inbox::Inbox(std::shared_ptr<Notifier> notifier, std::size_t capacity)
    : notifier_(std::move(notifier)),
      capacity_(capacity),
      confined_(notifier_->threading() == Threading::confined) {}

void Inbox::push_locked(wire::AnyMessage&& sample) {
  if (queue_.size() >= capacity_) {
    queue_.pop_front();
    overflowed_.fetch_add(1);
  }
  queue_.push_back(std::move(sample));
  size_.store(queue_.size(), std::memory_order_relaxed);
}

void Inbox::push(wire::AnyMessage&& sample) noexcept {
  try {
    if (confined_) {
      push_locked(std::move(sample));
    } else {
      std::lock_guard lock(mutex_);
      push_locked(std::move(sample));
    }
    notifier_->notify();
  } catch (...) {
    // Out of memory on a middleware thread: drop the sample rather than unwind into the vendor.
    overflowed_.fetch_add(1);
  }
}

void Inbox::drain(std::deque<wire::AnyMessage>& out) {
  std::unique_lock lock(mutex_, std::defer_lock);
  if (!confined_) lock.lock();
  if (out.empty()) {
    out.swap(queue_);  // the usual case: no sample moves, and queue_ keeps out's storage
  } else {
    for (auto& sample : queue_) out.push_back(std::move(sample));
    queue_.clear();
  }
  size_.store(0, std::memory_order_relaxed);
}

}  // namespace retreat::transport
