#pragma once
/// @file
/// The one narrow transport interface every process uses. Three implementations: in-memory
/// (tests, fast sweeps), Fast DDS and Cyclone DDS (idl/fastdds, idl/cyclonedds). Samples are
/// received on the caller's thread: wait(), then take() on each reader.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "retreat/transport/inbox.hpp"
#include "retreat/transport/qos.hpp"
#include "retreat/wire/messages.hpp"
#include "retreat/wire/topics.hpp"
#include "retreat/wire/validate.hpp"

namespace retreat::transport {

/// DDS Security (OMG DDS Security 1.1 built-in plugins: PKI-DH authentication, permissions
/// access control, AES-GCM-GMAC cryptography) of one participant: absolute or relative paths of
/// PEM and S/MIME files, the same files for both vendors (docs/security.md). All empty: security
/// off.
struct SecurityOptions {
  std::string identity_ca;           ///< CA certificate that signed every identity (PEM)
  std::string identity_certificate;  ///< this participant's certificate (PEM)
  std::string private_key;           ///< this participant's private key (PEM, unencrypted)
  std::string permissions_ca;        ///< CA certificate that signed the documents (PEM)
  std::string governance;            ///< the domain's governance document, signed (S/MIME)
  std::string permissions;           ///< this participant's permissions document, signed (S/MIME)
  bool enabled() const { return !identity_certificate.empty(); }
};

/// How a participant is created.
struct ParticipantOptions {
  int domain_id = 0;      ///< DDS domain id, 0..232 (the RTPS port mapping's range)
  std::string name;       ///< participant name shown in discovery, e.g. "retreat-agent"
  std::string user_data;  ///< announced in discovery, e.g. "retreat:agent:robot=3"
  std::string profile;    ///< vendor XML profile file; empty = built-in loopback-only settings
  SecurityOptions security{};  ///< DDS Security; default: off
  /// The swarm's domains, domain_id .. domain_id + domains - 1 (`dds.domains`): with more than
  /// one, make_transport joins every one of them (a ShardedTransport, sharded.hpp). 1..wire::max_domains.
  int domains = 1;
  /// Which of the swarm's domains a single-domain participant is on (0 = dds.domain): set for an
  /// agent on its robot's domain and for each participant of a ShardedTransport. The Fast DDS
  /// adapter moves a discovery-server profile's server to port + domain_index (one server per
  /// domain, docs/dds-profiles.md).
  int domain_index = 0;
};


/// The files of one identity (`robot_<id>`, `arena`, `bridge`) in a swarm PKI directory made by
/// deploy/security/make-swarm-pki.sh (`ca.pem`, `governance.p7s`, `<identity>/cert.pem`,
/// `key.pem`, `permissions.p7s`). Throws std::invalid_argument naming the directory and the
/// missing file when one is missing.
SecurityOptions swarm_identity(const std::string& pki_dir, const std::string& identity);

using wire::max_domain_id;

/// A remote endpoint matched with one of ours.
struct RemoteEndpoint {
  std::string guid;              ///< 32 hex digits (RTPS GUID: 12-byte prefix + entity id)
  std::string participant_guid;  ///< the GUID of the remote endpoint's participant
};

/// One of our endpoints and the remote endpoints it is matched with.
struct EndpointMatches {
  std::string topic;
  bool is_reader = false;
  std::vector<RemoteEndpoint> remotes;
};

/// A participant seen in discovery (including this one).
struct ParticipantInfo {
  std::string guid;  ///< participant GUID, 32 hex digits
  std::string name;  ///< participant name where the vendor carries it (Fast DDS), else empty
  std::string user_data;
};

enum class WriteResult { ok, timeout, error };

/// Counters of one reader. Samples are validated on take(); invalid ones are dropped here.
struct ReaderStats {
  std::uint64_t accepted = 0;
  std::array<std::uint64_t, 6> dropped{};  ///< indexed by wire::SampleFault (index 0 unused)
  std::uint64_t overflowed = 0;            ///< dropped because the inbox was full
  std::uint64_t undecodable = 0;           ///< the middleware could not decode them
  std::uint64_t dropped_total() const;
};

namespace detail {
/// The vendor side of one endpoint. Lives no longer than its transport.
class Port {
 public:
  virtual ~Port() = default;
  virtual std::vector<RemoteEndpoint> matched() const = 0;
};
class WriterPort : public Port {
 public:
  /// Writes @p sample (the port may move from it).
  virtual WriteResult write(wire::AnyMessage&& sample) = 0;
  virtual bool wait_for_acknowledgments(std::chrono::nanoseconds timeout) = 0;
};
class ReaderPort : public Port {};

/// The endpoints of one transport, so that matched_endpoints() can list them.
class PortRegistry {
 public:
  std::uint64_t add(const Port* port, std::string topic, bool is_reader);
  void remove(std::uint64_t id);
  std::vector<EndpointMatches> snapshot() const;

 private:
  struct Entry {
    const Port* port;
    std::string topic;
    bool is_reader;
  };
  mutable std::mutex mutex_;
  std::map<std::uint64_t, Entry> entries_;  // by id: creation order, and removal in O(log n)
  std::uint64_t next_id_ = 1;
};

/// Removes an endpoint from its registry when the typed writer or reader goes away.
class Registration {
 public:
  Registration(std::shared_ptr<PortRegistry> registry, std::uint64_t id)
      : registry_(std::move(registry)), id_(id) {}
  Registration(Registration&& other) noexcept
      : registry_(std::move(other.registry_)), id_(other.id_) {}
  Registration& operator=(Registration&& other) noexcept {
    if (this != &other) {
      release();
      registry_ = std::move(other.registry_);
      id_ = other.id_;
    }
    return *this;
  }
  ~Registration() { release(); }

 private:
  void release() {
    if (registry_) registry_->remove(id_);
    registry_.reset();
  }
  std::shared_ptr<PortRegistry> registry_;
  std::uint64_t id_ = 0;
};
}  // namespace detail

class Transport;

/// A typed writer on one topic. Move-only; must not outlive its Transport.
template <class M>
class Writer {
 public:
  WriteResult write(const M& sample) { return port_->write(wire::AnyMessage{sample}); }
  /// Blocks until every matched reliable reader acknowledged every sample written so far, or the
  /// timeout passes. Returns true when all were acknowledged.
  bool wait_for_acknowledgments(std::chrono::nanoseconds timeout) {
    return port_->wait_for_acknowledgments(timeout);
  }
  std::size_t matched_count() const { return port_->matched().size(); }
  std::vector<RemoteEndpoint> matched() const { return port_->matched(); }
  const std::string& topic() const { return topic_; }

 private:
  friend class Transport;
  Writer(std::unique_ptr<detail::WriterPort> port, std::string topic,
         const std::shared_ptr<detail::PortRegistry>& registry)
      : port_(std::move(port)),
        topic_(std::move(topic)),
        registration_(registry, registry->add(port_.get(), topic_, false)) {}
  std::unique_ptr<detail::WriterPort> port_;
  std::string topic_;
  detail::Registration registration_;  // after port_: deregistered before the port dies
};

/// A typed reader on one topic. take() runs on the caller's thread, validates every sample
/// (robot id against the per-robot topic, finite non-negative times, ranges) and drops and
/// counts invalid ones. Move-only; must not outlive its Transport.
template <class M>
class Reader {
 public:
  /// Every valid sample received since the last call, in arrival order.
  std::vector<M> take() {
    std::vector<M> out;
    take(out);
    return out;
  }
  /// The same into @p out (cleared first): a caller that keeps @p out allocates nothing per call.
  void take(std::vector<M>& out) {
    out.clear();
    if (inbox_->empty()) return;
    inbox_->drain([&](wire::AnyMessage&& any) {
      const auto fault = wire::validate(any, topic_robot_);
      if (fault != wire::SampleFault::ok) {
        ++stats_.dropped[static_cast<std::size_t>(fault)];
        return;
      }
      ++stats_.accepted;
      out.push_back(std::get<M>(std::move(any)));
    });
  }
  ReaderStats stats() const {
    ReaderStats s = stats_;
    s.overflowed = inbox_->overflowed();
    s.undecodable = inbox_->undecodable();
    return s;
  }
  std::size_t matched_count() const { return port_->matched().size(); }
  std::vector<RemoteEndpoint> matched() const { return port_->matched(); }
  const std::string& topic() const { return topic_; }

 private:
  friend class Transport;
  Reader(std::unique_ptr<detail::ReaderPort> port, std::shared_ptr<Inbox> inbox, std::string topic,
         const std::shared_ptr<detail::PortRegistry>& registry)
      : port_(std::move(port)),
        inbox_(std::move(inbox)),
        topic_(std::move(topic)),
        topic_robot_(wire::robot_of_topic(topic_)),
        registration_(registry, registry->add(port_.get(), topic_, true)) {}
  std::unique_ptr<detail::ReaderPort> port_;
  std::shared_ptr<Inbox> inbox_;
  std::string topic_;
  std::optional<wire::RobotId> topic_robot_;
  detail::Registration registration_;
  ReaderStats stats_;
};

/// A reader that keeps every sample as its bytes on the wire, undecoded (retreat-record). Samples
/// are not validated: a recorder keeps what was sent. Move-only; must not outlive its Transport.
class RawReader {
 public:
  /// Appends every sample received since the last call to @p out, in arrival order.
  void take(std::vector<RawSample>& out) { inbox_->drain_into(out); }
  /// Samples lost: the reader's inbox was full (the taker fell behind), the writer no longer had
  /// them when asked again (the DDS sample-lost status: a keep-last writer replaced them before
  /// this reader acknowledged them), or a sample could not be serialized again (Fast DDS).
  std::uint64_t overflowed() const { return inbox_->overflowed(); }
  std::size_t matched_count() const { return port_->matched().size(); }
  std::vector<RemoteEndpoint> matched() const { return port_->matched(); }
  const std::string& topic() const { return topic_; }
  wire::MessageKind kind() const { return kind_; }

 private:
  friend class Transport;
  RawReader(std::unique_ptr<detail::ReaderPort> port, std::shared_ptr<RawInbox> inbox,
            std::string topic, wire::MessageKind kind,
            const std::shared_ptr<detail::PortRegistry>& registry)
      : port_(std::move(port)),
        inbox_(std::move(inbox)),
        topic_(std::move(topic)),
        kind_(kind),
        registration_(registry, registry->add(port_.get(), topic_, true)) {}
  std::unique_ptr<detail::ReaderPort> port_;
  std::shared_ptr<RawInbox> inbox_;
  std::string topic_;
  wire::MessageKind kind_;
  detail::Registration registration_;
};

/// One participant on one domain.
class Transport {
 public:
  virtual ~Transport() = default;
  Transport(const Transport&) = delete;
  Transport& operator=(const Transport&) = delete;

  template <class M>
  Writer<M> create_writer(const TopicSpec& topic) {
    return Writer<M>(make_writer(wire::KindOf<M>::value, topic), topic.name, registry_);
  }
  template <class M>
  Reader<M> create_reader(const TopicSpec& topic) {
    auto inbox = std::make_shared<Inbox>(notifier_);
    auto port = make_reader(wire::KindOf<M>::value, topic, inbox);
    return Reader<M>(std::move(port), std::move(inbox), topic.name, registry_);
  }

  /// A reader of @p kind's samples on @p topic that keeps their CDR bytes (DDS transports only;
  /// the in-memory transport throws std::invalid_argument).
  RawReader create_raw_reader(wire::MessageKind kind, const TopicSpec& topic) {
    auto inbox = std::make_shared<RawInbox>(notifier_);
    auto port = make_raw_reader(kind, topic, inbox);
    return RawReader(std::move(port), std::move(inbox), topic.name, kind, registry_);
  }

  /// Blocks until any reader of this transport has received a sample since the previous call
  /// returned, or until the timeout. Returns true when something arrived.
  bool wait(std::chrono::nanoseconds timeout);
  /// Makes a wait() in progress on another thread, or the next one, return at once (as if a
  /// sample had arrived): for an event that is not a sample, e.g. a stop signal. Any thread.
  void wake();

  /// Our endpoints and what each is matched with (for isolation checks).
  std::vector<EndpointMatches> matched_endpoints() const { return registry_->snapshot(); }
  /// Participants seen in discovery on this domain, this one included.
  virtual std::vector<ParticipantInfo> participants() const = 0;
  /// The participant with this GUID if discovery has seen it. By default a scan of
  /// participants(); the in-memory transport, whose one bus can hold a swarm of 10⁵, looks it up.
  virtual std::optional<ParticipantInfo> participant(const std::string& guid) const;
  /// "inmemory", "fastdds" or "cyclonedds".
  virtual std::string_view vendor() const = 0;
  /// This participant's GUID (32 hex digits).
  virtual std::string guid() const = 0;

 protected:
  /// @p threading: Threading::confined when only the caller's thread ever writes to this
  /// transport's readers (a private in-memory bus stepped by one thread): no locks per sample.
  explicit Transport(Threading threading = Threading::shared)
      : notifier_(std::make_shared<Notifier>(threading)) {}
  virtual std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind,
                                                          const TopicSpec& topic) = 0;
  virtual std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind,
                                                          const TopicSpec& topic,
                                                          std::shared_ptr<Inbox> inbox) = 0;
  /// Raw readers: only the DDS transports have bytes on a wire to keep.
  virtual std::unique_ptr<detail::ReaderPort> make_raw_reader(wire::MessageKind kind,
                                                              const TopicSpec& topic,
                                                              std::shared_ptr<RawInbox> inbox);

 private:
  friend class ShardedTransport;  // creates its endpoints on its domains' transports
  std::shared_ptr<Notifier> notifier_;
  std::shared_ptr<detail::PortRegistry> registry_ = std::make_shared<detail::PortRegistry>();
  std::uint64_t seen_generation_ = 0;
};

/// The participants seen by @p transport that announced exactly @p user_data (e.g. the
/// recorders, wire::recorder_user_data), by GUID.
std::set<std::string> participants_announcing(const Transport& transport, std::string_view user_data);

/// The time left until @p deadline, never negative: for several waits (e.g. each writer's
/// wait_for_acknowledgments) under one deadline.
inline std::chrono::nanoseconds time_left(std::chrono::steady_clock::time_point deadline) {
  return std::max(std::chrono::nanoseconds::zero(),
                  std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - std::chrono::steady_clock::now()));
}

/// Whether @p remotes include an endpoint of every participant in @p participants.
bool matched_with_all(const std::vector<RemoteEndpoint>& remotes,
                      const std::set<std::string>& participants);

/// Formats 16 bytes as 32 lowercase hex digits (the GUID form used throughout).
std::string hex_guid(const unsigned char (&bytes)[16]);

/// Checks ParticipantOptions (domain range; with security, that every file exists); throws
/// std::invalid_argument naming the value and the valid range.
void validate(const ParticipantOptions& options);

}  // namespace retreat::transport
