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

void Inbox::push(wire::AnyMessage&& sample) noexcept {
  try {
    {
      const auto held = lock();
      std::size_t size = (has_first_ ? 1 : 0) + rest_.size();
      if (size >= capacity_) {  // drop the oldest
        if (has_first_) {
          has_first_ = false;
        } else {
          rest_.pop_front();
        }
        --size;
        overflowed_.fetch_add(1);
      }
      if (!has_first_ && rest_.empty()) {
        first_ = std::move(sample);
        has_first_ = true;
      } else {
        rest_.push_back(std::move(sample));
      }
      size_.store(size + 1, std::memory_order_relaxed);
    }
    notifier_->notify();
  } catch (...) {
    // Out of memory on a middleware thread: drop the sample rather than unwind into the vendor.
    overflowed_.fetch_add(1);
  }
}

RawInbox::RawInbox(std::shared_ptr<Notifier> notifier, std::size_t capacity)
    : notifier_(std::move(notifier)), capacity_(capacity) {}

void RawInbox::push(RawSample&& sample) noexcept {
  try {
    {
      std::lock_guard lock(mutex_);
      if (queue_.size() >= capacity_) {  // drop the oldest
        queue_.pop_front();
        overflowed_.fetch_add(1);
      }
      queue_.push_back(std::move(sample));
    }
    notifier_->notify();
  } catch (...) {
    overflowed_.fetch_add(1);  // out of memory on a middleware thread: drop, never unwind
  }
}

void RawInbox::drain_into(std::vector<RawSample>& out) {
  std::lock_guard lock(mutex_);
  for (auto& sample : queue_) out.push_back(std::move(sample));
  queue_.clear();
}

}  // namespace retreat::transport
