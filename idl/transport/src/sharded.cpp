#include "retreat/transport/sharded.hpp"

#include <stdexcept>

namespace retreat::transport {
namespace {

/// A reader of a shared topic: one reader per domain, all into the same inbox.
class FanInReaderPort final : public detail::ReaderPort {
 public:
  explicit FanInReaderPort(std::vector<std::unique_ptr<detail::ReaderPort>> ports) : ports_(std::move(ports)) {}
  std::vector<RemoteEndpoint> matched() const override {
    std::vector<RemoteEndpoint> out;
    for (const auto& port : ports_) {
      auto remotes = port->matched();
      out.insert(out.end(), std::make_move_iterator(remotes.begin()), std::make_move_iterator(remotes.end()));
    }
    return out;
  }

 private:
  std::vector<std::unique_ptr<detail::ReaderPort>> ports_;
};

}  // namespace

ShardedTransport::ShardedTransport(std::vector<std::unique_ptr<Transport>> shards) : shards_(std::move(shards)) {
  if (shards_.empty()) throw std::invalid_argument("a sharded transport needs at least one domain");
}

std::vector<ParticipantInfo> ShardedTransport::participants() const {
  std::vector<ParticipantInfo> out;
  for (const auto& shard : shards_) {
    auto seen = shard->participants();
    out.insert(out.end(), std::make_move_iterator(seen.begin()), std::make_move_iterator(seen.end()));
  }
  return out;
}

Transport& ShardedTransport::shard_of(const std::string& topic) const {
  const auto robot = wire::robot_of_topic(topic);
  if (!robot) return *shards_.front();
  return *shards_[wire::robot_domain(0, static_cast<int>(shards_.size()), *robot)];
}

std::unique_ptr<detail::WriterPort> ShardedTransport::make_writer(wire::MessageKind kind, const TopicSpec& topic) {
  return shard_of(topic.name).make_writer(kind, topic);
}

/// A reader of a per-robot topic on its robot's domain; of a shared topic on every domain.
template <class AnyInbox, class MakeOn>
std::unique_ptr<detail::ReaderPort> ShardedTransport::read(const TopicSpec& topic, std::shared_ptr<AnyInbox> inbox,
                                                           MakeOn make_on) {
  if (wire::robot_of_topic(topic.name)) return make_on(shard_of(topic.name), std::move(inbox));
  std::vector<std::unique_ptr<detail::ReaderPort>> ports;
  for (const auto& shard : shards_) ports.push_back(make_on(*shard, inbox));
  return std::make_unique<FanInReaderPort>(std::move(ports));
}

std::unique_ptr<detail::ReaderPort> ShardedTransport::make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                                  std::shared_ptr<Inbox> inbox) {
  return read(topic, std::move(inbox), [&](Transport& shard, std::shared_ptr<Inbox> in) {
    return shard.make_reader(kind, topic, std::move(in));
  });
}

std::unique_ptr<detail::ReaderPort> ShardedTransport::make_raw_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                                      std::shared_ptr<RawInbox> inbox) {
  return read(topic, std::move(inbox), [&](Transport& shard, std::shared_ptr<RawInbox> in) {
    return shard.make_raw_reader(kind, topic, std::move(in));
  });
}

}  // namespace retreat::transport
