#include "retreat/recorder/recorder.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "retreat/recorder/scene.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::recorder {
namespace {

/// How often discovery is checked for new agents [ns].
constexpr std::int64_t discovery_period_ns = 200'000'000;

/// The robot id in an agent's user data ("retreat:agent:robot=<id>"), if it is one.
std::optional<std::uint32_t> agent_robot(const std::string& user_data) {
  constexpr std::string_view head = "retreat:agent:robot=";
  if (user_data.compare(0, head.size(), head) != 0) return std::nullopt;
  std::uint32_t id = 0;
  const char* first = user_data.data() + head.size();
  const char* last = user_data.data() + user_data.size();
  const auto [end, error] = std::from_chars(first, last, id);
  if (error != std::errc() || end != last || first == last) return std::nullopt;
  return id;
}

}  // namespace

std::string schema_name(wire::MessageKind kind) {
  return std::string(wire::type_name(kind));  // the DDS type name is the IDL's scoped name
}

Recorder::Recorder(transport::Transport& transport, recording::McapWriter& mcap,
                   RecorderOptions options)
    : transport_(transport), mcap_(mcap), options_(std::move(options)) {
  using transport::QosIntent;
  // State topics are written keep-last-1 and transient-local; the recorder keeps every sample it
  // receives (keep all) and still gets each instance's newest sample when it joins late.
  constexpr QosIntent keep_all_state{transport::Reliability::reliable,
                                     transport::Durability::transient_local, 0};
  const auto& p = options_.prefix;
  add_topic(wire::MessageKind::arena_telemetry, {wire::arena_telemetry_topic(p), keep_all_state});
  add_topic(wire::MessageKind::poses, {wire::poses_topic(p), keep_all_state});
  if (options_.scene) {
    topics_.back()->drawn = true;
    const auto schema = mcap_.add_schema("foxglove.SceneUpdate", "jsonschema", std::string(scene_update_schema()));
    scene_channel_ = mcap_.add_channel(schema, p + "/scene", "json");
  }
  add_topic(wire::MessageKind::agent_status, {wire::agent_status_topic(p), keep_all_state});
  cover_robots(options_.robots);
}

void Recorder::add_topic(wire::MessageKind kind, const transport::TopicSpec& spec) {
  auto schema = schemas_.find(kind);
  if (schema == schemas_.end()) {
    schema = schemas_.emplace(kind, mcap_.add_schema(schema_name(kind), "omgidl",
                                                     std::string(message_idl()))).first;
  }
  auto reader = transport_.create_raw_reader(kind, spec);
  const auto channel = mcap_.add_channel(schema->second, spec.name, "cdr",
                                         {{"vendor", std::string(transport_.vendor())}});
  topics_.push_back(std::make_unique<Topic>(Topic{std::move(reader), channel}));
}

void Recorder::cover_robots(std::uint32_t end) {
  using transport::QosIntent;
  const auto& p = options_.prefix;
  QosIntent answers = QosIntent::control();
  if (options_.answers_kept) answers.durability = transport::Durability::transient_local;
  for (; covered_ < end; ++covered_) {
    const auto id = covered_;
    add_topic(wire::MessageKind::proximity_frame, {wire::proximity_topic(p, id), QosIntent::control()});
    add_topic(wire::MessageKind::decision, {wire::decision_topic(p, id), answers});
    if (options_.plans) add_topic(wire::MessageKind::decision, {wire::plan_topic(p, id), answers});
    if (id < options_.external_robots) {
      add_topic(wire::MessageKind::poses, {wire::tracked_pose_topic(p, id), QosIntent::control()});
    }
  }
}

void Recorder::watch_discovery(std::int64_t now_ns) {
  if (now_ns < next_discovery_check_) return;
  next_discovery_check_ = now_ns + discovery_period_ns;
  std::uint32_t end = covered_;
  for (const auto& participant : transport_.participants()) {
    if (const auto id = agent_robot(participant.user_data)) {
      end = std::max(end, std::min(*id, wire::RobotId{1u << 30}) + 1 + options_.spare);
    }
  }
  cover_robots(end);
}

std::size_t Recorder::poll(std::int64_t log_time_ns) {
  watch_discovery(log_time_ns);
  std::size_t written = 0;
  for (auto& topic : topics_) {
    scratch_.clear();
    topic->reader.take(scratch_);
    for (const auto& sample : scratch_) {
      const auto publish_time = static_cast<std::uint64_t>(std::max<std::int64_t>(sample.source_time_ns, 0));
      const auto bytes = std::as_bytes(std::span(sample.cdr));
      mcap_.write(topic->channel, topic->sequence++, static_cast<std::uint64_t>(log_time_ns), publish_time, bytes);
      if (topic->drawn) draw(bytes, static_cast<std::uint64_t>(log_time_ns), publish_time);
    }
    topic->messages += scratch_.size();
    written += scratch_.size();
  }
  messages_ += written;
  return written;
}

void Recorder::draw(std::span<const std::byte> cdr, std::uint64_t log_time, std::uint64_t publish_time) {
  const auto decoded = transport::decode_serialized(wire::MessageKind::poses, cdr);
  if (!decoded || wire::validate(*decoded, std::nullopt) != wire::SampleFault::ok) return;  // kept raw only
  const auto json = scene_update_json(std::get<wire::Poses>(*decoded), *options_.scene, publish_time);
  mcap_.write(*scene_channel_, scene_sequence_++, log_time, publish_time, std::as_bytes(std::span(json.data(), json.size())));
  ++scene_updates_;
}

std::uint64_t Recorder::overflowed() const {
  std::uint64_t total = 0;
  for (const auto& topic : topics_) total += topic->reader.overflowed();
  return total;
}

std::vector<ChannelCount> Recorder::counts() const {
  std::vector<ChannelCount> out;
  for (const auto& topic : topics_) {
    out.push_back({topic->reader.topic(), topic->messages, topic->reader.overflowed()});
  }
  return out;
}

}  // namespace retreat::recorder
