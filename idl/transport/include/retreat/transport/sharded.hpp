#pragma once
/// @file
/// One swarm over several DDS domains (`dds.domains`, docs/dds-profiles.md "Several domains").
/// Discovery is per domain: a hub announces every endpoint it has to every participant it
/// discovers, so a swarm of N robots on one domain costs the hub's participant 2N² endpoint
/// announcements. Over K domains, robot r's traffic is on domain D + r mod K: the arena (or the
/// bridge, or the recorder) has one participant per domain, each announcing 2N/K endpoints to
/// N/K agents.

#include <memory>
#include <vector>

#include "retreat/transport/transport.hpp"

namespace retreat::transport {

/// One transport made of one participant per domain (@p shards[i] on the swarm's domain D + i).
/// A per-robot topic's endpoint is created on its robot's domain; a writer of a shared topic on
/// the first domain (so that a reader joined to every domain gets each sample once); a reader of
/// a shared topic on every domain, into one inbox. wait() wakes for any of them.
class ShardedTransport final : public Transport {
 public:
  /// @p shards: at least one, all of one vendor.
  explicit ShardedTransport(std::vector<std::unique_ptr<Transport>> shards);

  /// Every domain's participants, ours included.
  std::vector<ParticipantInfo> participants() const override;
  std::string_view vendor() const override { return shards_.front()->vendor(); }
  /// The first domain's participant.
  std::string guid() const override { return shards_.front()->guid(); }
  std::size_t domains() const { return shards_.size(); }

 protected:
  std::unique_ptr<detail::WriterPort> make_writer(wire::MessageKind kind, const TopicSpec& topic) override;
  std::unique_ptr<detail::ReaderPort> make_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                  std::shared_ptr<Inbox> inbox) override;
  std::unique_ptr<detail::ReaderPort> make_raw_reader(wire::MessageKind kind, const TopicSpec& topic,
                                                      std::shared_ptr<RawInbox> inbox) override;

 private:
  Transport& shard_of(const std::string& topic) const;
  template <class AnyInbox, class MakeOn>
  std::unique_ptr<detail::ReaderPort> read(const TopicSpec& topic, std::shared_ptr<AnyInbox> inbox, MakeOn make_on);

  std::vector<std::unique_ptr<Transport>> shards_;
};

}  // namespace retreat::transport
