#include "retreat/transport/inmemory.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>

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
    std::map<std::uint32_t, std::deque<wire::AnyMessage>> history;  // transient-local only
  };
  struct ReaderEntry {
    std::uint64_t id;
    wire::MessageKind kind;
    QosIntent qos;
    RemoteEndpoint identity;
    std::shared_ptr<Inbox> inbox;
  };
  struct TopicEntry {
    std::vector<WriterEntry> writers;
    std::vector<ReaderEntry> readers;
  };

  std::uint64_t new_participant(ParticipantInfo info) {
    std::lock_guard lock(mutex_);
    const auto n = ++participants_counter_;
    info.guid = make_guid(n, 0x000001c1);
    participants_[n] = std::move(info);
    return n;
  }
  void remove_participant(std::uint64_t n) {
    std::lock_guard lock(mutex_);
    participants_.erase(n);
  }
  std::vector<ParticipantInfo> participants() const {
    std::lock_guard lock(mutex_);
    std::vector<ParticipantInfo> out;
    for (const auto& [n, info] : participants_) out.push_back(info);
    return out;
  }
  std::string participant_guid(std::uint64_t n) const {
    std::lock_guard lock(mutex_);
    return participants_.at(n).guid;
  }

  std::uint64_t add_writer(const std::string& topic, wire::MessageKind kind, QosIntent qos,
                           std::uint64_t participant) {
    std::lock_guard lock(mutex_);
    const auto id = ++endpoint_counter_;
    topics_[topic].writers.push_back(
        {id, kind, qos,
         {make_guid(participant, static_cast<std::uint32_t>(id)), participants_.at(participant).guid},
         {}});
    return id;
  }
  std::uint64_t add_reader(const std::string& topic, wire::MessageKind kind, QosIntent qos,
                           std::uint64_t participant, std::shared_ptr<Inbox> inbox) {
    std::lock_guard lock(mutex_);
    const auto id = ++endpoint_counter_;
    auto& entry = topics_[topic];
    ReaderEntry reader{id, kind, qos,
                       {make_guid(participant, static_cast<std::uint32_t>(id)),
                        participants_.at(participant).guid},
                       inbox};
    // Late joiner: replay what transient-local writers kept, instance by instance.
    for (const auto& w : entry.writers) {
      if (w.kind != kind || !compatible(w.qos, qos) || qos.durability != Durability::transient_local) {
        continue;
      }
      for (const auto& [key, samples] : w.history) {
        for (const auto& s : samples) inbox->push(wire::AnyMessage{s});
      }
    }
    entry.readers.push_back(std::move(reader));
    return id;
  }
  void remove(const std::string& topic, std::uint64_t id) {
    std::lock_guard lock(mutex_);
    auto& entry = topics_[topic];
    std::erase_if(entry.writers, [id](const auto& w) { return w.id == id; });
    std::erase_if(entry.readers, [id](const auto& r) { return r.id == id; });
  }

  void write(const std::string& topic, std::uint64_t writer_id, const wire::AnyMessage& sample) {
    std::lock_guard lock(mutex_);
    auto& entry = topics_[topic];
    auto w = std::find_if(entry.writers.begin(), entry.writers.end(),
                          [&](const auto& x) { return x.id == writer_id; });
    if (w == entry.writers.end()) return;
    if (w->qos.durability == Durability::transient_local) {
      auto& kept = w->history[instance_key(sample)];
      kept.push_back(sample);
      const std::size_t depth = w->qos.depth == 0 ? SIZE_MAX : w->qos.depth;
      while (kept.size() > depth) kept.pop_front();
    }
    for (auto& r : entry.readers) {
      if (r.kind == w->kind && compatible(w->qos, r.qos)) r.inbox->push(wire::AnyMessage{sample});
    }
  }

  std::vector<RemoteEndpoint> matched(const std::string& topic, std::uint64_t id) const {
    std::lock_guard lock(mutex_);
    std::vector<RemoteEndpoint> out;
    const auto it = topics_.find(topic);
    if (it == topics_.end()) return out;
    const auto& entry = it->second;
    for (const auto& w : entry.writers) {
      if (w.id == id) {
        for (const auto& r : entry.readers) {
          if (r.kind == w.kind && compatible(w.qos, r.qos)) out.push_back(r.identity);
        }
        return out;
      }
    }
    for (const auto& r : entry.readers) {
      if (r.id == id) {
        for (const auto& w : entry.writers) {
          if (r.kind == w.kind && compatible(w.qos, r.qos)) out.push_back(w.identity);
        }
      }
    }
    return out;
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, TopicEntry> topics_;
  std::map<std::uint64_t, ParticipantInfo> participants_;
  std::uint64_t participants_counter_ = 0;
  std::uint64_t endpoint_counter_ = 0;
};

namespace {

class InMemoryPort : public detail::WriterPort {
 public:
  InMemoryPort(std::shared_ptr<InMemoryBus> bus, std::string topic, std::uint64_t id)
      : bus_(std::move(bus)), topic_(std::move(topic)), id_(id) {}
  ~InMemoryPort() override { bus_->remove(topic_, id_); }
  WriteResult write(const wire::AnyMessage& sample) override {
    bus_->write(topic_, id_, sample);
    return WriteResult::ok;
  }
  // Delivery is synchronous: everything written is already in the readers' inboxes.
  bool wait_for_acknowledgments(std::chrono::nanoseconds) override { return true; }
  std::vector<RemoteEndpoint> matched() const override { return bus_->matched(topic_, id_); }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  std::string topic_;
  std::uint64_t id_;
};

class InMemoryReaderPort : public detail::ReaderPort {
 public:
  InMemoryReaderPort(std::shared_ptr<InMemoryBus> bus, std::string topic, std::uint64_t id)
      : bus_(std::move(bus)), topic_(std::move(topic)), id_(id) {}
  ~InMemoryReaderPort() override { bus_->remove(topic_, id_); }
  std::vector<RemoteEndpoint> matched() const override { return bus_->matched(topic_, id_); }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  std::string topic_;
  std::uint64_t id_;
};

class InMemoryTransport final : public Transport {
 public:
  InMemoryTransport(std::shared_ptr<InMemoryBus> bus, const ParticipantOptions& options)
      : bus_(std::move(bus)),
        participant_(bus_->new_participant({"", options.name, options.user_data})) {}
  ~InMemoryTransport() override { bus_->remove_participant(participant_); }

  std::vector<ParticipantInfo> participants() const override { return bus_->participants(); }
  std::string_view vendor() const override { return "inmemory"; }
  std::string guid() const override { return bus_->participant_guid(participant_); }

 protected:
  std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind,
                                                  const TopicSpec& topic) override {
    const auto id = bus_->add_writer(topic.name, kind, topic.qos, participant_);
    return std::make_unique<InMemoryPort>(bus_, topic.name, id);
  }
  std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                  std::shared_ptr<Inbox> inbox) override {
    const auto id = bus_->add_reader(topic.name, kind, topic.qos, participant_, std::move(inbox));
    return std::make_unique<InMemoryReaderPort>(bus_, topic.name, id);
  }

 private:
  std::shared_ptr<InMemoryBus> bus_;
  std::uint64_t participant_;
};

}  // namespace

std::shared_ptr<InMemoryBus> make_inmemory_bus() { return std::make_shared<InMemoryBus>(); }

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
