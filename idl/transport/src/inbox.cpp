#include "retreat/transport/inbox.hpp"

namespace retreat::transport {

void Notifier::notify() {
  {
    std::lock_guard lock(mutex_);
    ++generation_;
  }
  changed_.notify_all();
}

std::uint64_t Notifier::wait_after(std::uint64_t seen, std::chrono::nanoseconds timeout) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return generation_ != seen; });
  return generation_;
}

std::uint64_t Notifier::generation() const {
  std::lock_guard lock(mutex_);
  return generation_;
}

Inbox::Inbox(std::shared_ptr<Notifier> notifier, std::size_t capacity)
    : notifier_(std::move(notifier)), capacity_(capacity) {}

void Inbox::push(wire::AnyMessage&& sample) noexcept {
  try {
    {
      std::lock_guard lock(mutex_);
      if (queue_.size() >= capacity_) {
        queue_.pop_front();
        overflowed_.fetch_add(1);
      }
      queue_.push_back(std::move(sample));
    }
    notifier_->notify();
  } catch (...) {
    // Out of memory on a middleware thread: drop the sample rather than unwind into the vendor.
    overflowed_.fetch_add(1);
  }
}

void Inbox::drain(std::deque<wire::AnyMessage>& out) {
  std::lock_guard lock(mutex_);
  for (auto& sample : queue_) out.push_back(std::move(sample));
  queue_.clear();
}

}  // namespace retreat::transport
