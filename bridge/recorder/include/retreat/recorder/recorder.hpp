#pragma once
/// @file
/// retreat-record's work, apart from its program: readers that keep every sample of a swarm's
/// topics as its CDR bytes on the wire, written to an MCAP file (one channel per topic, the
/// schema as the OMG IDL text of idl/msg/retreat_msgs.idl). docs/recording.md.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "retreat/physics/params.hpp"
#include "retreat/recording/mcap_writer.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::recorder {

/// The text of idl/msg/retreat_msgs.idl, the wire contract, compiled in: each channel's schema.
std::string_view message_idl();

/// The MCAP schema name of a message kind: its IDL type's scoped name ("retreat::msg::Decision").
std::string schema_name(wire::MessageKind kind);

struct RecorderOptions {
  std::string prefix = "retreat";  ///< the swarm's topic prefix
  std::uint32_t robots = 0;         ///< per-robot topics of robots 0..robots-1 from the start
  bool plans = false;               ///< also `<prefix>/robot_<id>/plan` (run.plans)
  std::uint32_t external_robots = 0;  ///< robots 0..n-1 also have `tracked_pose` (real robots)
  /// run.recorders > 0: the agents' answer writers are transient-local then
  /// (QosIntent::kept_for_recorders), and the decision and plan readers ask for it, so that the
  /// answers written before a reader matched its writer are recorded too. A swarm started without
  /// run.recorders offers volatile answers, which such a reader does not match: the recorder
  /// takes the swarm's own scenario.
  bool answers_kept = false;
  /// Per-robot topics are kept ready this many ids beyond the highest robot an agent announced
  /// (an endless queue's agents start ahead of their robots).
  std::uint32_t spare = 8;
  /// The arena's geometry: with it, every `poses` sample is also written as a
  /// foxglove.SceneUpdate on `<prefix>/scene` (recorder/scene.hpp), for Foxglove's 3D panel.
  std::optional<physics::WorldParams> scene;
};

/// What was recorded on one topic.
struct ChannelCount {
  std::string topic;
  std::uint64_t messages = 0;
  std::uint64_t overflowed = 0;  ///< dropped: the recorder fell behind its readers
};

/// Reads a swarm's topics raw and writes them to an MCAP file. Single-threaded: the caller
/// alternates transport.wait() and poll().
class Recorder {
 public:
  /// Adds the schemas and creates the readers of @p options' topics. @p mcap must outlive this.
  /// @throws std::invalid_argument if @p transport keeps no serialized samples (in-memory).
  Recorder(transport::Transport& transport, recording::McapWriter& mcap, RecorderOptions options);

  /// Writes every sample that arrived, stamped @p log_time_ns (the recorder's clock, ns since
  /// the epoch), and adds readers for robots whose agents appeared in discovery. Returns the
  /// number of samples written.
  std::size_t poll(std::int64_t log_time_ns);

  /// Samples written so far.
  std::uint64_t messages() const { return messages_; }
  /// Samples lost because a reader's inbox was full, over every topic.
  std::uint64_t overflowed() const;
  /// Per topic, in the order the readers were created.
  std::vector<ChannelCount> counts() const;
  /// Scene updates written (one per decoded `poses` sample, with RecorderOptions::scene).
  std::uint64_t scene_updates() const { return scene_updates_; }
  /// The highest robot id with readers, plus one.
  std::uint32_t robots_covered() const { return covered_; }

 private:
  struct Topic {
    transport::RawReader reader;
    std::uint16_t channel;
    std::uint32_t sequence = 0;
    std::uint64_t messages = 0;
    bool drawn = false;  ///< the arena's poses: also written as scene updates
  };
  void add_topic(wire::MessageKind kind, const transport::TopicSpec& spec);
  void cover_robots(std::uint32_t end);  ///< readers for every robot id below @p end
  void watch_discovery(std::int64_t now_ns);
  /// Writes a scene update for one `poses` sample (undecodable or invalid ones: raw only).
  void draw(std::span<const std::byte> cdr, std::uint64_t log_time, std::uint64_t publish_time);

  transport::Transport& transport_;
  recording::McapWriter& mcap_;
  RecorderOptions options_;
  std::map<wire::MessageKind, std::uint16_t> schemas_;
  std::vector<std::unique_ptr<Topic>> topics_;
  std::vector<transport::RawSample> scratch_;
  std::uint32_t covered_ = 0;
  std::uint64_t messages_ = 0;
  std::int64_t next_discovery_check_ = 0;
  std::optional<std::uint16_t> scene_channel_;
  std::uint32_t scene_sequence_ = 0;
  std::uint64_t scene_updates_ = 0;
};

}  // namespace retreat::recorder
