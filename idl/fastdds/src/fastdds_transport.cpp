// The Fast DDS 2.9 adapter: maps QoS intents, types and errors; nothing else.
// Middleware threads only convert and enqueue (Inbox::push); nothing is thrown through them.

#include "retreat/transport/fastdds.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>

#include "fastdds_convert.hpp"
#include "fastdds_type_support.hpp"
#include "retreat_msgsPubSubTypes.h"
#include "retreat/core/paths.hpp"

namespace retreat::transport {
namespace {

namespace dds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using eprosima::fastrtps::types::ReturnCode_t;

/// The participant profile name a user's Fast DDS XML file must define.
constexpr const char* profile_name = "retreat_participant";

std::string to_hex(const rtps::GUID_t& guid) {
  unsigned char bytes[16];
  std::copy(std::begin(guid.guidPrefix.value), std::end(guid.guidPrefix.value), bytes);
  std::copy(std::begin(guid.entityId.value), std::end(guid.entityId.value), bytes + 12);
  return hex_guid(bytes);
}

std::string participant_hex(const rtps::GUID_t& guid) {
  return to_hex(rtps::GUID_t(guid.guidPrefix, rtps::c_EntityId_RTPSParticipant));
}

// ---- per-kind traits ---------------------------------------------------------------------
template <wire::MessageKind K> struct Traits;
template <> struct Traits<wire::MessageKind::proximity_frame> {
  using Plain = wire::ProximityFrame; using Vendor = msg::ProximityFrame; using PubSub = msg::ProximityFramePubSubType;
};
template <> struct Traits<wire::MessageKind::decision> {
  using Plain = wire::Decision; using Vendor = msg::Decision; using PubSub = msg::DecisionPubSubType;
};
template <> struct Traits<wire::MessageKind::agent_status> {
  using Plain = wire::AgentStatus; using Vendor = msg::AgentStatus; using PubSub = msg::AgentStatusPubSubType;
};
template <> struct Traits<wire::MessageKind::arena_telemetry> {
  using Plain = wire::ArenaTelemetry; using Vendor = msg::ArenaTelemetry; using PubSub = msg::ArenaTelemetryPubSubType;
};
template <> struct Traits<wire::MessageKind::poses> {
  using Plain = wire::Poses; using Vendor = msg::Poses; using PubSub = msg::PosesPubSubType;
};

template <class F>
decltype(auto) dispatch(wire::MessageKind kind, F&& f) {
  switch (kind) {
    case wire::MessageKind::proximity_frame: return f(Traits<wire::MessageKind::proximity_frame>{});
    case wire::MessageKind::decision: return f(Traits<wire::MessageKind::decision>{});
    case wire::MessageKind::agent_status: return f(Traits<wire::MessageKind::agent_status>{});
    case wire::MessageKind::arena_telemetry: return f(Traits<wire::MessageKind::arena_telemetry>{});
    case wire::MessageKind::poses: return f(Traits<wire::MessageKind::poses>{});
  }
  throw std::logic_error("unknown message kind");
}

// ---- QoS mapping -------------------------------------------------------------------------
template <class Qos>
void apply_common(Qos& q, const QosIntent& intent) {
  q.reliability().kind = intent.reliability == Reliability::reliable
                             ? dds::RELIABLE_RELIABILITY_QOS
                             : dds::BEST_EFFORT_RELIABILITY_QOS;
  q.durability().kind = intent.durability == Durability::transient_local
                            ? dds::TRANSIENT_LOCAL_DURABILITY_QOS
                            : dds::VOLATILE_DURABILITY_QOS;
  if (intent.depth == 0) {
    q.history().kind = dds::KEEP_ALL_HISTORY_QOS;
  } else {
    q.history().kind = dds::KEEP_LAST_HISTORY_QOS;
    q.history().depth = static_cast<int32_t>(intent.depth);
  }
  // Fast DDS 2.9's writer history refuses every write with LENGTH_UNLIMITED limits and insists
  // on max_samples >= max_instances * max_samples_per_instance, so the limits are finite and
  // generous: up to 4,096 instances (robots) and 4,096 unacknowledged samples per instance.
  q.resource_limits().max_instances = 4096;
  q.resource_limits().max_samples_per_instance = 4096;
  q.resource_limits().max_samples = 4096 * 4096;
  q.resource_limits().allocated_samples = 64;
  q.data_sharing().off();  // no shared-memory segments that could outlive a crashed process
}

dds::DataWriterQos writer_qos(dds::Publisher* publisher, const QosIntent& intent) {
  dds::DataWriterQos q = publisher->get_default_datawriter_qos();
  apply_common(q, intent);
  // Late joiners and lost packets are repaired quickly (ARCHITECTURE.md: Fast's default 3 s
  // heartbeat delays a Cyclone late joiner).
  q.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100'000'000);
  q.reliability().max_blocking_time = eprosima::fastrtps::Duration_t(5, 0);
  return q;
}

dds::DataReaderQos reader_qos(dds::Subscriber* subscriber, const QosIntent& intent) {
  dds::DataReaderQos q = subscriber->get_default_datareader_qos();
  apply_common(q, intent);
  return q;
}

// ---- matched endpoint tracking (updated from middleware threads) ---------------------------
class MatchSet {
 public:
  void update(const rtps::InstanceHandle_t& handle, int change) {
    rtps::GUID_t guid = rtps::iHandle2GUID(handle);
    std::lock_guard lock(mutex_);
    if (change > 0) {
      remotes_.insert(to_hex(guid));
      participants_[to_hex(guid)] = participant_hex(guid);
    } else if (change < 0) {
      remotes_.erase(to_hex(guid));
      participants_.erase(to_hex(guid));
    }
  }
  std::vector<RemoteEndpoint> snapshot() const {
    std::lock_guard lock(mutex_);
    std::vector<RemoteEndpoint> out;
    for (const auto& g : remotes_) out.push_back({g, participants_.at(g)});
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::set<std::string> remotes_;
  std::map<std::string, std::string> participants_;
};

class ParticipantListener final : public dds::DomainParticipantListener {
 public:
  void on_participant_discovery(dds::DomainParticipant*,
                                rtps::ParticipantDiscoveryInfo&& info) override {
    const auto guid = to_hex(info.info.m_guid);
    std::lock_guard lock(mutex_);
    if (info.status == rtps::ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT ||
        info.status == rtps::ParticipantDiscoveryInfo::CHANGED_QOS_PARTICIPANT) {
      const auto& data = info.info.m_userData.data_vec();
      participants_[guid] = {guid, info.info.m_participantName.to_string(),
                             std::string(data.begin(), data.end())};
    } else {
      participants_.erase(guid);
    }
  }
  std::vector<ParticipantInfo> snapshot() const {
    std::lock_guard lock(mutex_);
    std::vector<ParticipantInfo> out;
    for (const auto& [guid, info] : participants_) out.push_back(info);
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, ParticipantInfo> participants_;
};

// ---- ports ---------------------------------------------------------------------------------
class FastParticipant;

template <class T>
class FastWriterPort final : public detail::WriterPort, public dds::DataWriterListener {
 public:
  FastWriterPort(std::shared_ptr<FastParticipant> owner, dds::Publisher* publisher,
                 dds::Topic* topic, const QosIntent& intent);
  ~FastWriterPort() override;
  WriteResult write(wire::AnyMessage&& sample) override {
    auto vendor = fastdds::to_vendor(std::get<typename T::Plain>(sample));
    // Fast DDS 2.9's write() returns only success; a reliable KEEP_ALL writer fails when it has
    // blocked for max_blocking_time, which is the only failure we expect here.
    return writer_->write(&vendor) ? WriteResult::ok : WriteResult::timeout;
  }
  bool wait_for_acknowledgments(std::chrono::nanoseconds timeout) override {
    const auto ns = timeout.count();
    const eprosima::fastrtps::Duration_t max_wait(static_cast<int32_t>(ns / 1'000'000'000),
                                                  static_cast<uint32_t>(ns % 1'000'000'000));
    return writer_->wait_for_acknowledgments(max_wait) == ReturnCode_t::RETCODE_OK;
  }
  std::vector<RemoteEndpoint> matched() const override { return matches_.snapshot(); }
  void on_publication_matched(dds::DataWriter*, const dds::PublicationMatchedStatus& s) override {
    matches_.update(s.last_subscription_handle, s.current_count_change);
  }

 private:
  std::shared_ptr<FastParticipant> owner_;
  dds::Publisher* publisher_;
  dds::Topic* topic_;
  dds::DataWriter* writer_ = nullptr;
  MatchSet matches_;
};

template <class T>
class FastReaderPort final : public detail::ReaderPort, public dds::DataReaderListener {
 public:
  FastReaderPort(std::shared_ptr<FastParticipant> owner, dds::Subscriber* subscriber,
                 dds::Topic* topic, const QosIntent& intent, std::shared_ptr<Inbox> inbox);
  ~FastReaderPort() override;
  std::vector<RemoteEndpoint> matched() const override { return matches_.snapshot(); }
  void on_subscription_matched(dds::DataReader*, const dds::SubscriptionMatchedStatus& s) override {
    matches_.update(s.last_publication_handle, s.current_count_change);
  }
  void on_data_available(dds::DataReader* reader) override {
    typename T::Vendor sample;
    dds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) inbox_->push(wire::AnyMessage{fastdds::to_plain(sample)});
    }
  }

 private:
  std::shared_ptr<FastParticipant> owner_;
  dds::Subscriber* subscriber_;
  dds::Topic* topic_;
  std::shared_ptr<Inbox> inbox_;
  dds::DataReader* reader_ = nullptr;
  MatchSet matches_;
};

/// Fast DDS 2.9 hands a reader no serialized sample: the raw reader decodes it with the generated
/// type (as every reader here does) and serializes it again with the same generated code, a Fast
/// DDS writer's XCDR1 encoding. tests/recording compares a Fast DDS recording with a Cyclone DDS
/// one, which keeps the received bytes, for the same run: equal but for the end padding XCDR1
/// lets Cyclone DDS add (docs/recording.md).
template <class T>
class FastRawReaderPort final : public detail::ReaderPort, public dds::DataReaderListener {
 public:
  FastRawReaderPort(std::shared_ptr<FastParticipant> owner, dds::Subscriber* subscriber,
                    dds::Topic* topic, const QosIntent& intent, std::shared_ptr<RawInbox> inbox);
  ~FastRawReaderPort() override;
  std::vector<RemoteEndpoint> matched() const override { return matches_.snapshot(); }
  void on_subscription_matched(dds::DataReader*, const dds::SubscriptionMatchedStatus& s) override {
    matches_.update(s.last_publication_handle, s.current_count_change);
  }
  /// Samples a writer no longer had when this reader asked for them again (a keep-last writer
  /// replaced them before we acknowledged them): lost, and counted.
  void on_sample_lost(dds::DataReader*, const dds::SampleLostStatus& s) override {
    for (std::int32_t i = 0; i < s.total_count_change; ++i) inbox_->count_lost();
  }
  void on_data_available(dds::DataReader* reader) override {
    typename T::Vendor sample;
    dds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const auto size = type_.getSerializedSizeProvider(&sample)();
      rtps::SerializedPayload_t payload(size);
      if (!type_.serialize(&sample, &payload)) {
        inbox_->count_lost();  // not expected for a sample the same code decoded; counted if so
        continue;
      }
      inbox_->push(RawSample{std::vector<std::uint8_t>(payload.data, payload.data + payload.length),
                             info.source_timestamp.to_ns()});
    }
  }

 private:
  std::shared_ptr<FastParticipant> owner_;
  dds::Subscriber* subscriber_;
  dds::Topic* topic_;
  std::shared_ptr<RawInbox> inbox_;
  dds::DataReader* reader_ = nullptr;
  typename T::PubSub type_;
  MatchSet matches_;
};

// ---- participant -----------------------------------------------------------------------------
/// One discovery server per domain of a swarm on several domains: the participant on the swarm's
/// domain D + i (options.domain_index i) serves at, or is a client of, the profile's server port
/// + i, with byte 2 of the server's GUID prefix + i (ROS_DISCOVERY_SERVER's numbering), so that
/// the servers of one process differ. Any other profile is left as it is.
void shift_discovery_server(dds::DomainParticipantQos& qos, int domain_index) {
  if (domain_index == 0) return;
  using rtps::DiscoveryProtocol_t;
  const auto shift = [&](auto& locators) {
    for (auto& locator : locators) locator.port += static_cast<std::uint32_t>(domain_index);
  };
  const auto renumber = [&](rtps::GuidPrefix_t& prefix) {
    prefix.value[2] = static_cast<rtps::octet>(prefix.value[2] + domain_index);
  };
  auto& builtin = qos.wire_protocol().builtin;
  const auto protocol = builtin.discovery_config.discoveryProtocol;
  if (protocol == DiscoveryProtocol_t::SERVER || protocol == DiscoveryProtocol_t::BACKUP) {
    shift(builtin.metatrafficUnicastLocatorList);
    renumber(qos.wire_protocol().prefix);
  }
  if (protocol != DiscoveryProtocol_t::SIMPLE && protocol != DiscoveryProtocol_t::NONE) {
    for (auto& server : builtin.discovery_config.m_DiscoveryServers) {
      shift(server.metatrafficUnicastLocatorList);
      renumber(server.guidPrefix);
    }
  }
}

/// Owns the DomainParticipant and its publisher, subscriber and topics. Shared by the transport
/// and its ports so that the participant is deleted last.
class FastParticipant : public std::enable_shared_from_this<FastParticipant> {
 public:
  explicit FastParticipant(const ParticipantOptions& options) {
    auto* factory = dds::DomainParticipantFactory::get_instance();
    dds::DomainParticipantQos qos;
    if (options.profile.empty()) {
      qos = loopback_qos();
    } else {
      if (!retreat::is_regular_file(options.profile)) {
        throw std::invalid_argument("dds.profile = '" + options.profile +
                                    "': no such file (a Fast DDS XML profile file)");
      }
      if (!load_profile_file_once(factory, options.profile) ||
          factory->get_participant_qos_from_profile(profile_name, qos) != ReturnCode_t::RETCODE_OK) {
        throw std::invalid_argument("dds.profile = '" + options.profile +
                                    "': not a Fast DDS XML profile file with a participant "
                                    "profile named '" + profile_name + "'");
      }
    }
    shift_discovery_server(qos, options.domain_index);
    if (options.security.enabled()) add_security(qos, options.security);
    qos.name(options.name.empty() ? "retreat" : options.name);
    qos.user_data().data_vec(std::vector<rtps::octet>(options.user_data.begin(), options.user_data.end()));
    participant_ = factory->create_participant(static_cast<dds::DomainId_t>(options.domain_id), qos,
                                               &listener_, dds::StatusMask::none());
    if (participant_ == nullptr) {
      throw std::runtime_error("Fast DDS refused to create a participant on domain " +
                               std::to_string(options.domain_id) +
                               (options.security.enabled()
                                    ? " (DDS Security: check the identity, governance and permissions files)"
                                    : ""));
    }
    secure_ = options.security.enabled();
    publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
    if (publisher_ == nullptr || subscriber_ == nullptr) {
      throw std::runtime_error("Fast DDS refused to create a publisher or subscriber");
    }
  }

  ~FastParticipant() {
    if (participant_ == nullptr) return;
    participant_->delete_contained_entities();
    dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }

  dds::Topic* acquire_topic(wire::MessageKind kind, const std::string& name) {
    std::lock_guard lock(mutex_);
    auto& entry = topics_[name];
    if (entry.topic == nullptr) {
      const std::string type(wire::type_name(kind));
      if (participant_->find_type(type).empty()) {
        dispatch(kind, [&](auto traits) {
          dds::TypeSupport support(new fastdds::SafeTypeSupport<typename decltype(traits)::PubSub>());
          support.get()->auto_fill_type_information(false);
          support.get()->auto_fill_type_object(false);
          support.register_type(participant_);
        });
      }
      entry.topic = participant_->create_topic(name, type, dds::TOPIC_QOS_DEFAULT);
      if (entry.topic == nullptr) {
        throw std::runtime_error("Fast DDS refused to create topic '" + name + "' of type " + type +
                                 refusal_hint());
      }
    } else if (entry.topic->get_type_name() != wire::type_name(kind)) {
      throw std::invalid_argument("topic '" + name + "' already has type " +
                                  entry.topic->get_type_name());
    }
    ++entry.users;
    return entry.topic;
  }

  void release_topic(dds::Topic* topic) {
    std::lock_guard lock(mutex_);
    auto it = topics_.find(topic->get_name());
    if (it == topics_.end() || --it->second.users > 0) return;
    participant_->delete_topic(it->second.topic);
    topics_.erase(it);
  }

  /// Fast DDS keeps the profiles of every loaded file in one process-wide table and, when a
  /// second file defines "retreat_participant" again, logs an error and silently keeps the first
  /// one. So a process uses one profile file: loading it again is a no-op, another file is refused.
  static bool load_profile_file_once(dds::DomainParticipantFactory* factory, const std::string& path) {
    static std::mutex mutex;
    static std::string loaded;
    std::lock_guard lock(mutex);
    std::error_code error;  // a path the OS refuses is compared as written
    auto canonical = std::filesystem::weakly_canonical(path, error).string();
    if (error) canonical = path;
    if (loaded.empty()) {
      if (factory->load_XML_profiles_file(path) != ReturnCode_t::RETCODE_OK) return false;
      loaded = canonical;
    } else if (loaded != canonical) {
      throw std::invalid_argument("dds.profile = '" + path + "': this process already uses the Fast DDS "
                                  "profile file '" + loaded + "' (one profile file per process)");
    }
    return true;
  }

  /// Why an endpoint may have been refused, for the one-line error.
  std::string refusal_hint() const {
    return secure_ ? " (not granted by this participant's DDS Security permissions, or refused by the middleware)"
                   : "";
  }

  dds::DomainParticipant* participant() const { return participant_; }
  dds::Publisher* publisher() const { return publisher_; }
  dds::Subscriber* subscriber() const { return subscriber_; }
  const ParticipantListener& listener() const { return listener_; }

 private:
  /// Loopback only: UDPv4 on 127.0.0.1, no shared memory, no multicast (`lo` has none here).
  /// Discovery announcements go unicast to the well-known ports of participant ids 0..119 on
  /// 127.0.0.1. Fast DDS hands out participant ids per process in increasing order and never
  /// reuses one, so the range must cover every participant a process (or host) creates. Larger
  /// swarms use the discovery-server profile in deploy/dds/ (ARCHITECTURE.md, DDS facts).
  static dds::DomainParticipantQos loopback_qos() {
    dds::DomainParticipantQos qos;
    qos.transport().use_builtin_transports = false;
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.emplace_back("127.0.0.1");
    udp->maxInitialPeersRange = 120;  // ids 0..119: all a domain's port range holds
    qos.transport().user_transports.push_back(udp);
    rtps::Locator_t unicast;
    rtps::IPLocator::setIPv4(unicast, "127.0.0.1");
    qos.wire_protocol().builtin.initialPeersList.push_back(unicast);
    return qos;
  }

  /// The built-in plugins of Fast DDS 2.9 (PKI-DH, Access-Permissions, AES-GCM-GMAC), set as
  /// participant properties; certificates and documents as `file://` URIs of absolute paths.
  static void add_security(dds::DomainParticipantQos& qos, const SecurityOptions& s) {
    const auto uri = [](const std::string& path) {
      return "file://" + std::filesystem::absolute(path).string();
    };
    auto& p = qos.properties().properties();
    p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
    p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", uri(s.identity_ca));
    p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", uri(s.identity_certificate));
    p.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", uri(s.private_key));
    p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
    p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca", uri(s.permissions_ca));
    p.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", uri(s.governance));
    p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions", uri(s.permissions));
    p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  }

  struct TopicEntry {
    dds::Topic* topic = nullptr;
    int users = 0;
  };
  ParticipantListener listener_;
  dds::DomainParticipant* participant_ = nullptr;
  dds::Publisher* publisher_ = nullptr;
  dds::Subscriber* subscriber_ = nullptr;
  bool secure_ = false;
  std::mutex mutex_;
  std::map<std::string, TopicEntry> topics_;
};

template <class T>
FastWriterPort<T>::FastWriterPort(std::shared_ptr<FastParticipant> owner, dds::Publisher* publisher,
                                  dds::Topic* topic, const QosIntent& intent)
    : owner_(std::move(owner)), publisher_(publisher), topic_(topic) {
  writer_ = publisher_->create_datawriter(topic_, writer_qos(publisher_, intent), this,
                                          dds::StatusMask::publication_matched());
  if (writer_ == nullptr) {
    const auto name = topic_->get_name();
    owner_->release_topic(topic_);
    throw std::runtime_error("Fast DDS refused to create a writer on '" + name + "'" +
                             owner_->refusal_hint());
  }
}

template <class T>
FastWriterPort<T>::~FastWriterPort() {
  writer_->set_listener(nullptr);
  publisher_->delete_datawriter(writer_);
  owner_->release_topic(topic_);
}

/// Creates a reader of @p topic with @p listener, or releases the topic and throws (one line).
dds::DataReader* open_reader(FastParticipant& owner, dds::Subscriber* subscriber, dds::Topic* topic,
                             const QosIntent& intent, dds::DataReaderListener* listener,
                             const dds::StatusMask& mask) {
  auto* reader = subscriber->create_datareader(topic, reader_qos(subscriber, intent), listener, mask);
  if (reader == nullptr) {
    const auto name = topic->get_name();
    owner.release_topic(topic);
    throw std::runtime_error("Fast DDS refused to create a reader on '" + name + "'" + owner.refusal_hint());
  }
  return reader;
}

/// Detaches the listener first (no callback into a port being destroyed), then deletes.
void close_reader(FastParticipant& owner, dds::Subscriber* subscriber, dds::Topic* topic,
                  dds::DataReader* reader) {
  reader->set_listener(nullptr);
  subscriber->delete_datareader(reader);
  owner.release_topic(topic);
}

template <class T>
FastReaderPort<T>::FastReaderPort(std::shared_ptr<FastParticipant> owner,
                                  dds::Subscriber* subscriber, dds::Topic* topic,
                                  const QosIntent& intent, std::shared_ptr<Inbox> inbox)
    : owner_(std::move(owner)), subscriber_(subscriber), topic_(topic), inbox_(std::move(inbox)) {
  reader_ = open_reader(*owner_, subscriber_, topic_, intent, this,
                        dds::StatusMask::subscription_matched() << dds::StatusMask::data_available());
}

template <class T>
FastReaderPort<T>::~FastReaderPort() {
  close_reader(*owner_, subscriber_, topic_, reader_);
}

template <class T>
FastRawReaderPort<T>::FastRawReaderPort(std::shared_ptr<FastParticipant> owner,
                                        dds::Subscriber* subscriber, dds::Topic* topic,
                                        const QosIntent& intent, std::shared_ptr<RawInbox> inbox)
    : owner_(std::move(owner)), subscriber_(subscriber), topic_(topic), inbox_(std::move(inbox)) {
  reader_ = open_reader(*owner_, subscriber_, topic_, intent, this,
                        dds::StatusMask::subscription_matched() << dds::StatusMask::data_available()
                                                                << dds::StatusMask::sample_lost());
}

template <class T>
FastRawReaderPort<T>::~FastRawReaderPort() {
  close_reader(*owner_, subscriber_, topic_, reader_);
}

class FastTransport final : public Transport {
 public:
  explicit FastTransport(const ParticipantOptions& options)
      : participant_(std::make_shared<FastParticipant>(options)) {}

  std::vector<ParticipantInfo> participants() const override {
    auto out = participant_->listener().snapshot();
    const auto qos = participant_->participant()->get_qos();
    const auto& data = qos.user_data().data_vec();
    out.push_back({guid(), qos.name().to_string(), std::string(data.begin(), data.end())});
    return out;
  }
  std::string_view vendor() const override { return "fastdds"; }
  std::string guid() const override { return to_hex(participant_->participant()->guid()); }

 protected:
  std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind,
                                                  const TopicSpec& topic) override {
    auto* t = participant_->acquire_topic(kind, topic.name);
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::WriterPort> {
      return std::make_unique<FastWriterPort<decltype(traits)>>(participant_, participant_->publisher(),
                                                               t, topic.qos);
    });
  }
  std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                  std::shared_ptr<Inbox> inbox) override {
    auto* t = participant_->acquire_topic(kind, topic.name);
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::ReaderPort> {
      return std::make_unique<FastReaderPort<decltype(traits)>>(
          participant_, participant_->subscriber(), t, topic.qos, std::move(inbox));
    });
  }
  std::unique_ptr<detail::ReaderPort> make_raw_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                      std::shared_ptr<RawInbox> inbox) override {
    auto* t = participant_->acquire_topic(kind, topic.name);
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::ReaderPort> {
      return std::make_unique<FastRawReaderPort<decltype(traits)>>(
          participant_, participant_->subscriber(), t, topic.qos, std::move(inbox));
    });
  }

 private:
  std::shared_ptr<FastParticipant> participant_;
};

}  // namespace

std::unique_ptr<Transport> make_fastdds_transport(const ParticipantOptions& options) {
  validate(options);
  return std::make_unique<FastTransport>(options);
}

std::optional<wire::AnyMessage> decode_fastdds(wire::MessageKind kind, std::span<const std::byte> bytes) {
  if (bytes.size() > 0xFFFF'0000U) return std::nullopt;  // no sample is that large (a payload's length is 32-bit)
  return dispatch(kind, [&](auto traits) -> std::optional<wire::AnyMessage> {
    using T = decltype(traits);
    static thread_local fastdds::SafeTypeSupport<typename T::PubSub> type;  // one per type and thread
    rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
    if (!bytes.empty()) std::memcpy(payload.data, bytes.data(), bytes.size());
    payload.length = static_cast<std::uint32_t>(bytes.size());
    typename T::Vendor sample;
    if (!type.deserialize(&payload, &sample)) return std::nullopt;
    return wire::AnyMessage{fastdds::to_plain(sample)};
  });
}

}  // namespace retreat::transport

