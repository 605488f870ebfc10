#include "retreat/transport/transport.hpp"

#include "retreat/core/paths.hpp"

#include <algorithm>
#include <filesystem>
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

void Transport::wake() { notifier_->notify(); }

std::unique_ptr<detail::ReaderPort> Transport::make_raw_reader(wire::MessageKind, const TopicSpec& topic,
                                                                std::shared_ptr<RawInbox>) {
  throw std::invalid_argument("topic '" + topic.name + "': the " + std::string(vendor()) +
                              " transport carries no serialized samples to record (use fastdds "
                              "or cyclonedds)");
}

std::optional<ParticipantInfo> Transport::participant(const std::string& guid) const {
  for (auto& p : participants()) {
    if (p.guid == guid) return std::move(p);
  }
  return std::nullopt;
}

std::set<std::string> participants_announcing(const Transport& transport, std::string_view user_data) {
  std::set<std::string> out;
  for (const auto& p : transport.participants()) {
    if (p.user_data == user_data) out.insert(p.guid);
  }
  return out;
}

bool matched_with_all(const std::vector<RemoteEndpoint>& remotes,
                      const std::set<std::string>& participants) {
  return std::all_of(participants.begin(), participants.end(), [&](const std::string& p) {
    return std::any_of(remotes.begin(), remotes.end(),
                       [&](const RemoteEndpoint& r) { return r.participant_guid == p; });
  });
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
  if (const int most = wire::max_domains_from(options.domain_id); options.domains < 1 || options.domains > most) {
    throw std::invalid_argument("dds.domains = " + std::to_string(options.domains) + ": must be an integer in 1.." +
                                std::to_string(most) + " (domains " + std::to_string(options.domain_id) + ".." +
                                std::to_string(max_domain_id) + " are left from dds.domain)");
  }
  const auto& s = options.security;
  if (!s.enabled()) return;
  for (const auto* file : {&s.identity_ca, &s.identity_certificate, &s.private_key,
                           &s.permissions_ca, &s.governance, &s.permissions}) {
    if (!retreat::is_regular_file(*file)) {
      throw std::invalid_argument("DDS Security file '" + *file +
                                  "': no such file (make the swarm's PKI with "
                                  "deploy/security/make-swarm-pki.sh)");
    }
  }
}

SecurityOptions swarm_identity(const std::string& pki_dir, const std::string& identity) {
  const std::filesystem::path dir(pki_dir);
  const auto file = [&](const std::filesystem::path& relative) {
    const auto path = dir / relative;
    if (!retreat::is_regular_file(path)) {
      throw std::invalid_argument("dds.security_dir = '" + pki_dir + "': no " + relative.string() +
                                  " (identity '" + identity +
                                  "'; make it with deploy/security/make-swarm-pki.sh)");
    }
    return path.string();
  };
  SecurityOptions out;
  out.identity_ca = file("ca.pem");
  out.permissions_ca = out.identity_ca;
  out.governance = file("governance.p7s");
  out.identity_certificate = file(std::filesystem::path(identity) / "cert.pem");
  out.private_key = file(std::filesystem::path(identity) / "key.pem");
  out.permissions = file(std::filesystem::path(identity) / "permissions.p7s");
  return out;
}

namespace detail {

std::uint64_t PortRegistry::add(const Port* port, std::string topic, bool is_reader) {
  std::lock_guard lock(mutex_);
  entries_.emplace(next_id_, Entry{port, std::move(topic), is_reader});
  return next_id_++;
}

void PortRegistry::remove(std::uint64_t id) {
  std::lock_guard lock(mutex_);
  entries_.erase(id);
}

std::vector<EndpointMatches> PortRegistry::snapshot() const {
  std::lock_guard lock(mutex_);
  std::vector<EndpointMatches> out;
  out.reserve(entries_.size());
  for (const auto& [id, e] : entries_) out.push_back({e.topic, e.is_reader, e.port->matched()});
  return out;
}

}  // namespace detail
}  // namespace retreat::transport
