#include "retreat/transport/inmemory.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>
#include <unordered_map>
#include <utility>

namespace retreat::transport {
namespace {

std::uint32_t instance_key(const wire::AnyMessage& m) {
  return std::visit(
      [](const auto& s) -> std::uint32_t {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, wire::ArenaTelemetry> || std::is_same_v<T, wire::Poses>) {
          return s.arena_id;
        } else {
          return s.robot_id;
        }
      },
      m);
}

std::string make_guid(std::uint64_t participant, std::uint32_t entity) {
  unsigned char bytes[16] = {0x72, 0x74, 0x6d, 0x65};  // "rtme": retreat in-memory
  for (int i = 0; i < 8; ++i) bytes[4 + i] = static_cast<unsigned char>(participant >> (8 * (7 - i)));
  for (int i = 0; i < 4; ++i) bytes[12 + i] = static_cast<unsigned char>(entity >> (8 * (3 - i)));
  return hex_guid(bytes);
}

bool compatible(const QosIntent& writer, const QosIntent& reader) {
  if (reader.reliability == Reliability::reliable && writer.reliability != Reliability::reliable) {
    return false;
  }
  return !(reader.durability == Durability::transient_local &&
           writer.durability != Durability::transient_local);
}

}  // namespace

class InMemoryBus {
 public:
  struct WriterEntry {
    std::uint64_t id;
    wire::MessageKind kind;
    QosIntent qos;
    RemoteEndpoint identity;
    std::unordered_map<std::uint32_t, std::deque<wire::AnyMessage>> history;  // transient-local only
  };
  struct ReaderEntry {
    std::uint64_t id;
    wire::MessageKind kind;
    QosIntent qos;
    RemoteEndpoint identity;
    std::shared_ptr<Inbox> inbox;
  };
  /// One topic: its endpoints, and a version that changes whenever they do (a writer's list of
  /// matched inboxes is rebuilt only then).
  struct TopicEntry {
    std::map<std::uint64_t, WriterEntry> writers;  // by id: creation order; removal in O(log n)
    std::map<std::uint64_t, ReaderEntry> readers;
    std::uint64_t version = 0;
  };
  /// What a writer resolved once: its topic, and the inboxes it delivers to at the topic's
  /// version `seen`.
  struct WriterRoute {
    TopicEntry* topic = nullptr;
    std::uint64_t id = 0;
    std::uint64_t seen = ~std::uint64_t{0};      ///< the topic's version when last resolved
    std::uint64_t seen_bus = ~std::uint64_t{0};  ///< the bus's version when last checked
    WriterEntry* self = nullptr;
    std::vector<Inbox*> targets;
    Inbox* only = nullptr;  ///< targets[0] when it is the only one (a robot's own topic): no hop
  };

  explicit InMemoryBus(Threading threading) : threading_(threading) {}
  Threading threading() const { return threading_; }

  std::uint64_t new_participant(ParticipantInfo info) {
    const auto lock = guard();
    const auto n = ++participants_counter_;
    info.guid = make_guid(n, 0x000001c1);
    by_guid_[info.guid] = n;
    participants_[n] = std::move(info);
    return n;
  }
  void remove_participant(std::uint64_t n) {
    const auto lock = guard();
    const auto found = participants_.find(n);
    if (found == participants_.end()) return;
    by_guid_.erase(found->second.guid);
    participants_.erase(found);
  }
  std::optional<ParticipantInfo> participant(const std::string& guid) const {
    const auto lock = guard();
    const auto found = by_guid_.find(guid);
    if (found == by_guid_.end()) return std::nullopt;
    return participants_.at(found->second);
  }
  std::vector<ParticipantInfo> participants() const {
    const auto lock = guard();
    std::vector<ParticipantInfo> out;
    for (const auto& [n, info] : participants_) out.push_back(info);
    return out;
  }
  std::string participant_guid(std::uint64_t n) const {
    const auto lock = guard();
    return participants_.at(n).guid;
  }

  WriterRoute add_writer(const std::string& topic, wire::MessageKind kind, QosIntent qos,
                         std::uint64_t participant) {
    const auto lock = guard();
    const auto id = ++endpoint_counter_;
    auto& entry = topic_entry(topic);
    entry.writers.emplace(
        id, WriterEntry{id, kind, qos,
                        {make_guid(participant, static_cast<std::uint32_t>(id)), participants_.at(participant).guid},
                        {}});
    ++entry.version;
    ++version_;
    WriterRoute route;
    route.topic = &entry;
    route.id = id;
    return route;
  }
  std::pair<TopicEntry*, std::uint64_t> add_reader(const std::string& topic, wire::MessageKind kind,
                                                   QosIntent qos, std::uint64_t participant,
                                                   std::shared_ptr<Inbox> inbox) {
    const auto lock = guard();
    const auto id = ++endpoint_counter_;
    auto& entry = topic_entry(topic);
    ReaderEntry reader{id, kind, qos,
                       {make_guid(participant, static_cast<std::uint32_t>(id)),
                        participants_.at(participant).guid},
                       inbox};
    // Late joiner: replay what transient-local writers kept, instance by instance (ascending
    // instance key, as a keyed history would hand them over).
    for (const auto& [wid, w] : entry.writers) {
      if (w.kind != kind || !compatible(w.qos, qos) || qos.durability != Durability::transient_local) {
        continue;
      }
      std::vector<std::uint32_t> keys;
      for (const auto& kept : w.history) keys.push_back(kept.first);
      std::sort(keys.begin(), keys.end());
      for (const auto key : keys) {
        for (const auto& sample : w.history.at(key)) inbox->push(wire::AnyMessage{sample});
      }
    }
    entry.readers.emplace(id, std::move(reader));
    ++entry.version;
    ++version_;
    return {&entry, id};
  }
  void remove(TopicEntry* entry, std::uint64_t id) {
    const auto lock = guard();
    entry->writers.erase(id);
    entry->readers.erase(id);
    ++entry->version;
    ++version_;
  }

  void write(WriterRoute& route, wire::AnyMessage&& sample) {
    const auto lock = guard();
    // The bus's version (one line every write reads) first: while no endpoint anywhere changed,
    // the topic's own entry (one of thousands) is not read at all.
    if (route.seen_bus != version_) {
      route.seen_bus = version_;
      if (route.seen != route.topic->version) resolve(route);
    }
    if (route.self == nullptr) return;
    if (route.self->qos.durability == Durability::transient_local) {
      auto& kept = route.self->history[instance_key(sample)];
      kept.push_back(sample);
      const std::size_t depth = route.self->qos.depth == 0 ? SIZE_MAX : route.self->qos.depth;
      while (kept.size() > depth) kept.pop_front();
    }
    if (route.only != nullptr) {
      route.only->push(std::move(sample));
      return;
    }
    // Every reader but the last gets a copy; the last one gets the sample itself.
    const std::size_t n = route.targets.size();
    for (std::size_t i = 0; i + 1 < n; ++i) route.targets[i]->push(wire::AnyMessage{sample});
    if (n > 0) route.targets[n - 1]->push(std::move(sample));
  }

  std::vector<RemoteEndpoint> matched(const TopicEntry* entry, std::uint64_t id) const {
    const auto lock = guard();
    std::vector<RemoteEndpoint> out;
    if (const auto writer = entry->writers.find(id); writer != entry->writers.end()) {
      for (const auto& [rid, r] : entry->readers) {
        if (r.kind == writer->second.kind && compatible(writer->second.qos, r.qos)) out.push_back(r.identity);
      }
    } else if (const auto reader = entry->readers.find(id); reader != entry->readers.end()) {
      for (const auto& [wid, w] : entry->writers) {
        if (reader->second.kind == w.kind && compatible(w.qos, reader->second.qos)) out.push_back(w.identity);
      }
    }
    return out;
  }

 private:
  /// A lock on the bus, or none on a confined one.
  std::unique_lock<std::mutex> guard() const {
    return threading_ == Threading::confined ? std::unique_lock<std::mutex>()
                                             : std::unique_lock<std::mutex>(mutex_);
  }
  TopicEntry& topic_entry(const std::string& topic) {
    auto& slot = topics_[topic];
    if (!slot) slot = std::make_unique<TopicEntry>();
    return *slot;
  }
  /// Rebuilds @p route for its topic's current endpoints (called with the lock held).
  static void resolve(WriterRoute& route) {
    auto& entry = *route.topic;
    route.seen = entry.version;
    route.targets.clear();
    route.only = nullptr;
    const auto self = entry.writers.find(route.id);
    route.self = self == entry.writers.end() ? nullptr : &self->second;
    if (route.self == nullptr) return;
    for (auto& [rid, r] : entry.readers) {
      if (r.kind == route.self->kind && compatible(route.self->qos, r.qos)) route.targets.push_back(r.inbox.get());
    }
    route.only = route.targets.size() == 1 ? route.targets.front() : nullptr;
  }

  Threading threading_;
  mutable std::mutex mutex_;
  std::uint64_t version_ = 0;  ///< changes whenever any topic's endpoints do
  std::map<std::string, std::unique_ptr<TopicEntry>> topics_;  // entries never move or go
  std::map<std::uint64_t, ParticipantInfo> participants_;
  std::unordered_map<std::string, std::uint64_t> by_guid_;  ///< a swarm in one process has 10⁵ of them
  std::uint64_t participants_counter_ = 0;
  std::uint64_t endpoint_counter_ = 0;
};

namespace {

class InMemoryPort : public detail::WriterPort {
 public:
  InMemoryPort(std::shared_ptr<InMemoryBus> bus, InMemoryBus::WriterRoute route)
      : bus_(std::move(bus)), route_(std::move(route)) {}
  ~InMemoryPort() override { bus_->remove(route_.topic, route_.id); }
  WriteResult write(wire::AnyMessage&& sample) override {
    bus_->write(route_, std::move(sample));
    return WriteResult::ok;
  }
  // Delivery is synchronous: everything written is already in the readers' inboxes.
  bool wait_for_acknowledgments(std::chrono::nanoseconds) override { return true; }
  std::vector<RemoteEndpoint> matched() const override { return bus_->matched(route_.topic, route_.id); }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  InMemoryBus::WriterRoute route_;
};

class InMemoryReaderPort : public detail::ReaderPort {
 public:
  InMemoryReaderPort(std::shared_ptr<InMemoryBus> bus, InMemoryBus::TopicEntry* topic, std::uint64_t id)
      : bus_(std::move(bus)), topic_(topic), id_(id) {}
  ~InMemoryReaderPort() override { bus_->remove(topic_, id_); }
  std::vector<RemoteEndpoint> matched() const override { return bus_->matched(topic_, id_); }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  InMemoryBus::TopicEntry* topic_;
  std::uint64_t id_;
};

class InMemoryTransport final : public Transport {
 public:
  InMemoryTransport(std::shared_ptr<InMemoryBus> bus, const ParticipantOptions& options)
      : Transport(bus->threading()),
        bus_(std::move(bus)),
        participant_(bus_->new_participant({"", options.name, options.user_data})) {}
  ~InMemoryTransport() override { bus_->remove_participant(participant_); }

  std::vector<ParticipantInfo> participants() const override { return bus_->participants(); }
  std::optional<ParticipantInfo> participant(const std::string& guid) const override { return bus_->participant(guid); }
  std::string_view vendor() const override { return "inmemory"; }
  std::string guid() const override { return bus_->participant_guid(participant_); }

 protected:
  std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind,
                                                  const TopicSpec& topic) override {
    return std::make_unique<InMemoryPort>(bus_, bus_->add_writer(topic.name, kind, topic.qos, participant_));
  }
  std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                  std::shared_ptr<Inbox> inbox) override {
    const auto [entry, id] = bus_->add_reader(topic.name, kind, topic.qos, participant_, std::move(inbox));
    return std::make_unique<InMemoryReaderPort>(bus_, entry, id);
  }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  std::uint64_t participant_;
};

}  // namespace

std::shared_ptr<InMemoryBus> make_inmemory_bus(Threading threading) {
  return std::make_shared<InMemoryBus>(threading);
}

std::shared_ptr<InMemoryBus> inmemory_bus_for_domain(int domain_id) {
  static std::mutex mutex;
  static std::map<int, std::weak_ptr<InMemoryBus>> buses;
  std::lock_guard lock(mutex);
  auto bus = buses[domain_id].lock();
  if (!bus) {
    bus = make_inmemory_bus();
    buses[domain_id] = bus;
  }
  return bus;
}

std::unique_ptr<Transport> make_inmemory_transport(std::shared_ptr<InMemoryBus> bus,
                                                   const ParticipantOptions& options) {
  validate(options);
  return std::make_unique<InMemoryTransport>(std::move(bus), options);
}

}  // namespace retreat::transport
