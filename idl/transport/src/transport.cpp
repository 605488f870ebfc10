#include "retreat/transport/transport.hpp"

#include <algorithm>
#include <stdexcept>

namespace retreat::transport {

std::uint64_t ReaderStats::dropped_total() const {
  std::uint64_t total = overflowed + undecodable;
  for (const auto n : dropped) total += n;
  return total;
}

bool Transport::wait(std::chrono::nanoseconds timeout) {
  const auto now = notifier_->wait_after(seen_generation_, timeout);
  const bool arrived = now != seen_generation_;
  seen_generation_ = now;
  return arrived;
}

std::string hex_guid(const unsigned char (&bytes)[16]) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string out(32, '0');
  for (std::size_t i = 0; i < 16; ++i) {
    out[2 * i] = digits[bytes[i] >> 4];
    out[2 * i + 1] = digits[bytes[i] & 0x0f];
  }
  return out;
}

void validate(const ParticipantOptions& options) {
  if (options.domain_id < 0 || options.domain_id > max_domain_id) {
    throw std::invalid_argument("dds.domain = " + std::to_string(options.domain_id) +
                                ": must be an integer in 0.." + std::to_string(max_domain_id));
  }
}

namespace detail {

std::uint64_t PortRegistry::add(const Port* port, std::string topic, bool is_reader) {
  std::lock_guard lock(mutex_);
  entries_.push_back({next_id_, port, std::move(topic), is_reader});
  return next_id_++;
}

void PortRegistry::remove(std::uint64_t id) {
  std::lock_guard lock(mutex_);
  std::erase_if(entries_, [id](const Entry& e) { return e.id == id; });
}

std::vector<EndpointMatches> PortRegistry::snapshot() const {
  std::lock_guard lock(mutex_);
  std::vector<EndpointMatches> out;
  out.reserve(entries_.size());
  for (const auto& e : entries_) out.push_back({e.topic, e.is_reader, e.port->matched()});
  return out;
}

}  // namespace detail
}  // namespace retreat::transport
