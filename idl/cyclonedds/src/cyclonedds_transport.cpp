// The Cyclone DDS 0.10 adapter: maps QoS intents, types and errors; nothing else.
// Middleware threads only convert and enqueue (Inbox::push); nothing is thrown through them.

#include "retreat/transport/cyclonedds.hpp"

#include <dds/dds.h>
#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsi/ddsi_serdata.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "cyclonedds_convert.hpp"

namespace retreat::transport {
namespace {

/// The built-in configuration: loopback only. `lo` has no MULTICAST flag on these machines, so
/// multicast is forced on for it; without it Cyclone falls back to unicast discovery with
/// participant indices and runs out of them at about ten processes (ARCHITECTURE.md). Multicast
/// is for participant announcements only (AllowMulticast spdp, as deploy/dds/cyclonedds-
/// loopback.xml): a reader that advertised a multicast data locator made Fast DDS 2.9 agents of a
/// mixed swarm abort in their statistics module (an assertion in OutputTrafficManager) once a
/// second Cyclone DDS reader of their topics (a recorder, an observer) joined. Each
/// participant also takes a participant index (well-known unicast ports 7410 + 250·domain +
/// 2·index, up to the 120 a domain's port range holds) and announces itself to those ports on
/// 127.0.0.1: Fast DDS participants, which do not use multicast here, listen and announce on
/// exactly those ports, so the two vendors find each other at once.
constexpr const char* loopback_config =
    "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>"
    "<NetworkInterface name=\"lo\" multicast=\"true\"/>"
    "</Interfaces><AllowMulticast>spdp</AllowMulticast></General>"
    "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>119</MaxAutoParticipantIndex>"
    "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
    "</Domain></CycloneDDS>";

std::string hex(const dds_guid_t& guid) {
  unsigned char bytes[16];
  std::copy(std::begin(guid.v), std::end(guid.v), bytes);
  return hex_guid(bytes);
}

std::string fail(const std::string& what, dds_return_t rc) {
  return "Cyclone DDS: " + what + " failed: " + dds_strretcode(rc);
}

/// Cyclone keeps one configuration per domain and process; this counts our participants on each.
class DomainRegistry {
 public:
  static DomainRegistry& instance() {
    static DomainRegistry registry;
    return registry;
  }
  void acquire(int domain_id, const std::string& config) {
    std::lock_guard lock(mutex_);
    auto& d = domains_[domain_id];
    if (d.users == 0) {
      const auto handle = dds_create_domain(static_cast<dds_domainid_t>(domain_id), config.c_str());
      if (handle < 0) {
        domains_.erase(domain_id);
        throw std::invalid_argument("dds.profile: Cyclone DDS rejected the configuration for domain " +
                                    std::to_string(domain_id) + " (" + dds_strretcode(handle) + ")");
      }
      d.handle = handle;
      d.config = config;
    } else if (d.config != config) {
      throw std::invalid_argument("dds.profile: domain " + std::to_string(domain_id) +
                                  " already runs with another Cyclone configuration in this process");
    }
    ++d.users;
  }
  void release(int domain_id) {
    std::lock_guard lock(mutex_);
    auto it = domains_.find(domain_id);
    if (it == domains_.end() || --it->second.users > 0) return;
    dds_delete(it->second.handle);
    domains_.erase(it);
  }

 private:
  struct Domain {
    dds_entity_t handle = 0;
    std::string config;
    int users = 0;
  };
  std::mutex mutex_;
  std::map<int, Domain> domains_;
};

// ---- per-kind traits ---------------------------------------------------------------------------
template <class P, class V>
struct TraitsBase {
  using Plain = P;
  using Vendor = V;
};
struct FrameTraits : TraitsBase<wire::ProximityFrame, retreat_msg_ProximityFrame> {
  static const dds_topic_descriptor_t* desc() { return &retreat_msg_ProximityFrame_desc; }
};
struct DecisionTraits : TraitsBase<wire::Decision, retreat_msg_Decision> {
  static const dds_topic_descriptor_t* desc() { return &retreat_msg_Decision_desc; }
};
struct StatusTraits : TraitsBase<wire::AgentStatus, retreat_msg_AgentStatus> {
  static const dds_topic_descriptor_t* desc() { return &retreat_msg_AgentStatus_desc; }
};
struct TelemetryTraits : TraitsBase<wire::ArenaTelemetry, retreat_msg_ArenaTelemetry> {
  static const dds_topic_descriptor_t* desc() { return &retreat_msg_ArenaTelemetry_desc; }
};
struct PosesTraits : TraitsBase<wire::Poses, retreat_msg_Poses> {
  static const dds_topic_descriptor_t* desc() { return &retreat_msg_Poses_desc; }
};

template <class F>
decltype(auto) dispatch(wire::MessageKind kind, F&& f) {
  switch (kind) {
    case wire::MessageKind::proximity_frame: return f(FrameTraits{});
    case wire::MessageKind::decision: return f(DecisionTraits{});
    case wire::MessageKind::agent_status: return f(StatusTraits{});
    case wire::MessageKind::arena_telemetry: return f(TelemetryTraits{});
    case wire::MessageKind::poses: return f(PosesTraits{});
  }
  throw std::logic_error("unknown message kind");
}

/// QoS for both endpoint kinds. XCDR1 only: Fast DDS 2.9 cannot read XCDR2.
class Qos {
 public:
  explicit Qos(const QosIntent& intent) : qos_(dds_create_qos()) {
    dds_qset_reliability(qos_,
                         intent.reliability == Reliability::reliable ? DDS_RELIABILITY_RELIABLE
                                                                     : DDS_RELIABILITY_BEST_EFFORT,
                         DDS_SECS(5));
    dds_qset_durability(qos_, intent.durability == Durability::transient_local
                                  ? DDS_DURABILITY_TRANSIENT_LOCAL
                                  : DDS_DURABILITY_VOLATILE);
    const auto history = intent.depth == 0 ? DDS_HISTORY_KEEP_ALL : DDS_HISTORY_KEEP_LAST;
    const auto depth = intent.depth == 0 ? 0 : static_cast<int32_t>(intent.depth);
    dds_qset_history(qos_, history, depth);
    // What a transient-local writer keeps for late joiners is its durability service history
    // (Cyclone DDS; keep-last 1 by default), not its history: the same depth, as Fast DDS keeps.
    dds_qset_durability_service(qos_, 0, history, depth, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED);
    dds_qset_resource_limits(qos_, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
    const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
    dds_qset_data_representation(qos_, 1, &xcdr1);
  }
  ~Qos() { dds_delete_qos(qos_); }
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  const dds_qos_t* get() const { return qos_; }

 private:
  dds_qos_t* qos_;
};

using MatchedHandles = dds_return_t (*)(dds_entity_t, dds_instance_handle_t*, size_t);
using MatchedData = dds_builtintopic_endpoint_t* (*)(dds_entity_t, dds_instance_handle_t);

std::vector<RemoteEndpoint> matched_of(dds_entity_t entity, MatchedHandles handles_of,
                                       MatchedData data_of) {
  std::vector<dds_instance_handle_t> handles(64);
  dds_return_t n = 0;
  while ((n = handles_of(entity, handles.data(), handles.size())) > static_cast<dds_return_t>(handles.size())) {
    handles.resize(static_cast<std::size_t>(n));
  }
  std::vector<RemoteEndpoint> out;
  for (dds_return_t i = 0; i < n; ++i) {
    dds_builtintopic_endpoint_t* data = data_of(entity, handles[static_cast<std::size_t>(i)]);
    if (data == nullptr) continue;  // unmatched in between
    out.push_back({hex(data->key), hex(data->participant_key)});
    dds_builtintopic_free_endpoint(data);
  }
  return out;
}

template <class T>
class CycloneWriterPort final : public detail::WriterPort {
 public:
  CycloneWriterPort(dds_entity_t participant, const std::string& topic, const QosIntent& intent) {
    topic_ = dds_create_topic(participant, T::desc(), topic.c_str(), nullptr, nullptr);
    if (topic_ < 0) throw std::runtime_error(fail("create topic '" + topic + "'", topic_));
    Qos qos(intent);
    writer_ = dds_create_writer(participant, topic_, qos.get(), nullptr);
    if (writer_ < 0) {
      dds_delete(topic_);
      throw std::runtime_error(fail("create writer on '" + topic + "'", writer_));
    }
  }
  ~CycloneWriterPort() override {
    dds_delete(writer_);
    dds_delete(topic_);
  }
  WriteResult write(wire::AnyMessage&& sample) override {
    typename T::Vendor vendor{};
    const auto& plain = std::get<typename T::Plain>(sample);
    dds_return_t rc;
    if constexpr (std::is_same_v<T, PosesTraits>) {
      cyclonedds::PosesScratch scratch;
      cyclonedds::to_vendor(plain, vendor, scratch);
      rc = dds_write(writer_, &vendor);
    } else {
      cyclonedds::to_vendor(plain, vendor);
      rc = dds_write(writer_, &vendor);
    }
    if (rc == DDS_RETCODE_OK) return WriteResult::ok;
    return rc == DDS_RETCODE_TIMEOUT ? WriteResult::timeout : WriteResult::error;
  }
  bool wait_for_acknowledgments(std::chrono::nanoseconds timeout) override {
    return dds_wait_for_acks(writer_, static_cast<dds_duration_t>(timeout.count())) == DDS_RETCODE_OK;
  }
  std::vector<RemoteEndpoint> matched() const override {
    return matched_of(writer_, &dds_get_matched_subscriptions, &dds_get_matched_subscription_data);
  }

 private:
  dds_entity_t topic_ = 0;
  dds_entity_t writer_ = 0;
};

/// A topic and a reader of it with a listener, created together and deleted together: the
/// listener is detached first, so that no callback reaches a port being destroyed. A port
/// declares it last, so that it goes before the inbox and the lock its callbacks use.
class ReaderEntities {
 public:
  /// Takes @p listener (deleted here, whatever happens); throws one line if Cyclone refuses the
  /// topic or the reader.
  ReaderEntities(dds_entity_t participant, const dds_topic_descriptor_t* desc, const std::string& name,
                 const QosIntent& intent, dds_listener_t* listener) {
    topic_ = dds_create_topic(participant, desc, name.c_str(), nullptr, nullptr);
    if (topic_ < 0) {
      dds_delete_listener(listener);
      throw std::runtime_error(fail("create topic '" + name + "'", topic_));
    }
    Qos qos(intent);
    reader_ = dds_create_reader(participant, topic_, qos.get(), listener);
    dds_delete_listener(listener);
    if (reader_ < 0) {
      dds_delete(topic_);
      throw std::runtime_error(fail("create reader on '" + name + "'", reader_));
    }
  }
  ~ReaderEntities() {
    dds_set_listener(reader_, nullptr);
    dds_delete(reader_);
    dds_delete(topic_);
  }
  ReaderEntities(const ReaderEntities&) = delete;
  ReaderEntities& operator=(const ReaderEntities&) = delete;
  dds_entity_t reader() const { return reader_; }
  std::vector<RemoteEndpoint> matched() const {
    return matched_of(reader_, &dds_get_matched_publications, &dds_get_matched_publication_data);
  }

 private:
  dds_entity_t topic_ = 0;
  dds_entity_t reader_ = 0;
};

template <class T>
class CycloneReaderPort final : public detail::ReaderPort {
 public:
  CycloneReaderPort(dds_entity_t participant, const std::string& topic, const QosIntent& intent,
                    std::shared_ptr<Inbox> inbox)
      : inbox_(std::move(inbox)), entities_(participant, T::desc(), topic, intent, listener_for(this)) {
    // Samples that arrived before the listener was attached (transient-local replay).
    drain(entities_.reader());
  }
  std::vector<RemoteEndpoint> matched() const override { return entities_.matched(); }

 private:
  static dds_listener_t* listener_for(CycloneReaderPort* self) {
    dds_listener_t* listener = dds_create_listener(self);
    dds_lset_data_available(listener, &CycloneReaderPort::on_data_available);
    return listener;
  }
  static void on_data_available(dds_entity_t reader, void* self) {
    static_cast<CycloneReaderPort*>(self)->drain(reader);
  }
  void drain(dds_entity_t reader) noexcept {
    constexpr std::size_t batch = 64;
    void* samples[batch] = {};
    dds_sample_info_t infos[batch];
    std::lock_guard lock(drain_mutex_);
    for (;;) {
      const dds_return_t n = dds_take(reader, samples, infos, batch, batch);
      if (n <= 0) break;
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        try {
          inbox_->push(wire::AnyMessage{
              cyclonedds::to_plain(*static_cast<const typename T::Vendor*>(samples[i]))});
        } catch (...) {
          inbox_->count_undecodable();
        }
      }
      dds_return_loan(reader, samples, n);
      if (static_cast<std::size_t>(n) < batch) break;
    }
  }

  std::shared_ptr<Inbox> inbox_;
  std::mutex drain_mutex_;
  ReaderEntities entities_;  // last: deleted first
};

/// Keeps each sample's serialized form (dds_takecdr): the bytes as received, header included.
class CycloneRawReaderPort final : public detail::ReaderPort {
 public:
  CycloneRawReaderPort(dds_entity_t participant, const dds_topic_descriptor_t* desc,
                       const std::string& topic, const QosIntent& intent,
                       std::shared_ptr<RawInbox> inbox)
      : inbox_(std::move(inbox)), entities_(participant, desc, topic, intent, listener_for(this)) {
    drain(entities_.reader());
  }
  std::vector<RemoteEndpoint> matched() const override { return entities_.matched(); }

 private:
  static dds_listener_t* listener_for(CycloneRawReaderPort* self) {
    dds_listener_t* listener = dds_create_listener(self);
    dds_lset_data_available(listener, &CycloneRawReaderPort::on_data_available);
    dds_lset_sample_lost(listener, &CycloneRawReaderPort::on_sample_lost);
    return listener;
  }
  /// Samples the writer no longer had when this reader asked for them again: lost, and counted.
  static void on_sample_lost(dds_entity_t, const dds_sample_lost_status_t status, void* self) {
    auto& inbox = *static_cast<CycloneRawReaderPort*>(self)->inbox_;
    for (std::int32_t i = 0; i < status.total_count_change; ++i) inbox.count_lost();
  }
  static void on_data_available(dds_entity_t reader, void* self) {
    static_cast<CycloneRawReaderPort*>(self)->drain(reader);
  }
  void drain(dds_entity_t reader) noexcept {
    constexpr std::uint32_t batch = 64;
    ddsi_serdata* samples[batch] = {};
    dds_sample_info_t infos[batch];
    std::lock_guard lock(drain_mutex_);
    for (;;) {
      const dds_return_t n = dds_takecdr(reader, samples, batch, infos, 0);
      if (n <= 0) break;
      for (dds_return_t i = 0; i < n; ++i) {
        if (infos[i].valid_data) {
          try {
            RawSample raw;
            raw.cdr.resize(ddsi_serdata_size(samples[i]));
            ddsi_serdata_to_ser(samples[i], 0, raw.cdr.size(), raw.cdr.data());
            raw.source_time_ns = infos[i].source_timestamp;
            inbox_->push(std::move(raw));
          } catch (...) {
            // out of memory: the sample is lost like an overflow; never unwind into Cyclone
          }
        }
        ddsi_serdata_unref(samples[i]);
      }
      if (static_cast<std::uint32_t>(n) < batch) break;
    }
  }

  std::shared_ptr<RawInbox> inbox_;
  std::mutex drain_mutex_;
  ReaderEntities entities_;  // last: deleted first
};

class CycloneTransport final : public Transport {
 public:
  explicit CycloneTransport(const ParticipantOptions& options) : domain_id_(options.domain_id) {
    DomainRegistry::instance().acquire(domain_id_, config_of(options));
    dds_qos_t* qos = dds_create_qos();
    if (!options.user_data.empty()) {
      dds_qset_userdata(qos, options.user_data.data(), options.user_data.size());
    }
    dds_qset_entity_name(qos, options.name.empty() ? "retreat" : options.name.c_str());
    if (options.security.enabled()) add_security(qos, options.security);
    participant_ = dds_create_participant(static_cast<dds_domainid_t>(domain_id_), qos, nullptr);
    dds_delete_qos(qos);
    if (participant_ < 0) {
      DomainRegistry::instance().release(domain_id_);
      throw std::runtime_error(
          fail("create participant on domain " + std::to_string(domain_id_), participant_) +
          (options.security.enabled()
               ? " (DDS Security: check the identity, governance and permissions files)"
               : ""));
    }
    participants_reader_ =
        dds_create_reader(participant_, DDS_BUILTIN_TOPIC_DCPSPARTICIPANT, nullptr, nullptr);
  }
  ~CycloneTransport() override {
    dds_delete(participant_);
    DomainRegistry::instance().release(domain_id_);
  }

  std::vector<ParticipantInfo> participants() const override {
    std::vector<ParticipantInfo> out;
    // dds_read returns at most as many samples as there is room for: grow until one read holds
    // every participant (a swarm on one domain has hundreds or thousands).
    std::vector<void*> samples;
    std::vector<dds_sample_info_t> infos;
    dds_return_t n = 0;
    for (std::size_t room = 256;; room *= 2) {
      samples.assign(room, nullptr);
      infos.resize(room);
      n = dds_read(participants_reader_, samples.data(), infos.data(), room, static_cast<uint32_t>(room));
      if (n < static_cast<dds_return_t>(room)) break;
      dds_return_loan(participants_reader_, samples.data(), n);
    }
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data || infos[i].instance_state != DDS_IST_ALIVE) continue;
      const auto* p = static_cast<const dds_builtintopic_participant_t*>(samples[i]);
      ParticipantInfo info{hex(p->key), "", ""};
      void* data = nullptr;
      size_t size = 0;
      if (dds_qget_userdata(p->qos, &data, &size) && data != nullptr) {
        info.user_data.assign(static_cast<const char*>(data), size);
        dds_free(data);
      }
      char* name = nullptr;
      if (dds_qget_entity_name(p->qos, &name) && name != nullptr) {
        info.name = name;
        dds_free(name);
      }
      out.push_back(std::move(info));
    }
    if (n > 0) dds_return_loan(participants_reader_, samples.data(), n);
    return out;
  }
  std::string_view vendor() const override { return "cyclonedds"; }
  std::string guid() const override {
    dds_guid_t g;
    dds_get_guid(participant_, &g);
    return hex(g);
  }

 protected:
  std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind,
                                                  const TopicSpec& topic) override {
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::WriterPort> {
      return std::make_unique<CycloneWriterPort<decltype(traits)>>(participant_, topic.name,
                                                                  topic.qos);
    });
  }
  std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                  std::shared_ptr<Inbox> inbox) override {
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::ReaderPort> {
      return std::make_unique<CycloneReaderPort<decltype(traits)>>(participant_, topic.name,
                                                                  topic.qos, std::move(inbox));
    });
  }
  std::unique_ptr<detail::ReaderPort> make_raw_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                      std::shared_ptr<RawInbox> inbox) override {
    return dispatch(kind, [&](auto traits) -> std::unique_ptr<detail::ReaderPort> {
      return std::make_unique<CycloneRawReaderPort>(participant_, decltype(traits)::desc(), topic.name,
                                                    topic.qos, std::move(inbox));
    });
  }

 private:
  /// The plugins of libddsc0debian (libdds_security_{auth,ac,crypto}.so, by absolute path: the
  /// directory is not on the loader's path), set as `dds.sec.*` participant properties;
  /// certificates and documents as `file:` URIs of absolute paths.
  static void add_security(dds_qos_t* qos, const SecurityOptions& s) {
    const auto uri = [](const std::string& path) {
      return "file:" + std::filesystem::absolute(path).string();
    };
    const std::string dir = RETREAT_CYCLONE_SECURITY_DIR;
    const auto plugin = [&](const char* kind, const std::string& library, const char* init,
                            const char* finalize) {
      const std::string key = std::string("dds.sec.") + kind + ".library.";
      dds_qset_prop(qos, (key + "path").c_str(), (dir + "/libdds_security_" + library + ".so").c_str());
      dds_qset_prop(qos, (key + "init").c_str(), init);
      dds_qset_prop(qos, (key + "finalize").c_str(), finalize);
    };
    plugin("auth", "auth", "init_authentication", "finalize_authentication");
    plugin("access", "ac", "init_access_control", "finalize_access_control");
    plugin("crypto", "crypto", "init_crypto", "finalize_crypto");
    dds_qset_prop(qos, "dds.sec.auth.identity_ca", uri(s.identity_ca).c_str());
    dds_qset_prop(qos, "dds.sec.auth.identity_certificate", uri(s.identity_certificate).c_str());
    dds_qset_prop(qos, "dds.sec.auth.private_key", uri(s.private_key).c_str());
    dds_qset_prop(qos, "dds.sec.access.permissions_ca", uri(s.permissions_ca).c_str());
    dds_qset_prop(qos, "dds.sec.access.governance", uri(s.governance).c_str());
    dds_qset_prop(qos, "dds.sec.access.permissions", uri(s.permissions).c_str());
  }

  static std::string config_of(const ParticipantOptions& options) {
    if (options.profile.empty()) return loopback_config;
    std::ifstream in(options.profile);
    if (!in) {
      throw std::invalid_argument("dds.profile = '" + options.profile +
                                  "': cannot read the file (a Cyclone DDS XML configuration)");
    }
    std::stringstream text;
    text << in.rdbuf();
    const auto content = text.str();
    if (content.find("<CycloneDDS") == std::string::npos) {
      throw std::invalid_argument("dds.profile = '" + options.profile +
                                  "': not a Cyclone DDS XML configuration (no <CycloneDDS> element)");
    }
    return content;
  }

  int domain_id_;
  dds_entity_t participant_ = 0;
  dds_entity_t participants_reader_ = 0;
};

}  // namespace

std::unique_ptr<Transport> make_cyclonedds_transport(const ParticipantOptions& options) {
  validate(options);
  return std::make_unique<CycloneTransport>(options);
}

std::optional<wire::AnyMessage> decode_cyclonedds(wire::MessageKind kind, std::span<const std::byte> bytes) {
  // What Cyclone's default serdata does with a received sample: check the encapsulation header
  // (XCDR1 or XCDR2, either byte order), normalize the body against the type's marshalling ops
  // (bounds, byte order, booleans, sequence lengths), read it into a sample.
  if (bytes.size() < 4 || bytes.size() > 0xFFFF'0000U) return std::nullopt;
  const auto identifier = static_cast<std::uint16_t>(std::to_integer<unsigned>(bytes[0]) << 8 |
                                                     std::to_integer<unsigned>(bytes[1]));
  std::uint32_t version = 0;
  if (identifier == 0x0000 || identifier == 0x0001) version = 1;       // CDR_BE, CDR_LE
  else if (identifier == 0x0006 || identifier == 0x0007) version = 2;  // CDR2_BE, CDR2_LE
  else return std::nullopt;
  const bool big_endian = (identifier & 1) == 0;
  const bool bswap = big_endian != (DDSRT_ENDIAN == DDSRT_BIG_ENDIAN);
  const auto body_size = static_cast<std::uint32_t>(bytes.size() - 4);
  std::vector<std::uint64_t> storage(body_size / 8 + 1);  // 8-byte aligned, as a receive buffer
  auto* body = reinterpret_cast<char*>(storage.data());
  std::memcpy(body, bytes.data() + 4, body_size);
  return dispatch(kind, [&](auto traits) -> std::optional<wire::AnyMessage> {
    using T = decltype(traits);
    const auto* ops = T::desc()->m_ops;
    std::uint32_t offset = 0;
    if (dds_stream_normalize_data(body, &offset, body_size, bswap, version, ops) == nullptr) return std::nullopt;
    typename T::Vendor sample;
    std::memset(&sample, 0, sizeof sample);
    dds_istream_t in;
    dds_istream_init(&in, body_size, body, version);
    dds_stream_read(&in, reinterpret_cast<char*>(&sample), ops);
    dds_istream_fini(&in);
    std::optional<wire::AnyMessage> out;
    try {
      out.emplace(cyclonedds::to_plain(sample));
    } catch (...) {  // out of memory while copying a sequence: undecodable here
      out.reset();
    }
    dds_stream_free_sample(&sample, ops);
    return out;
  });
}

}  // namespace retreat::transport
