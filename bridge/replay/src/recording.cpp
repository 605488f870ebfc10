#include "retreat/replay/recording.hpp"

#include <optional>

#include "retreat/core/paths.hpp"
#include "retreat/recording/mcap_reader.hpp"
#include "retreat/scenario/json.hpp"
#include "retreat/transport/factory.hpp"
#include "retreat/wire/topics.hpp"
#include "retreat/wire/validate.hpp"

namespace retreat::replay {
namespace {

/// What a channel carries, from its topic (named as on DDS) and its schema's name.
enum class Carries { frames, decisions, plans, telemetry, statuses, poses, tracked_poses, foreign };

struct ChannelRole {
  Carries carries = Carries::foreign;
  std::optional<wire::RobotId> robot;
  wire::MessageKind kind = wire::MessageKind::proximity_frame;
};

ChannelRole role_of(const recording::McapChannel& channel, const recording::McapContents& contents,
                    const std::string& prefix) {
  ChannelRole r;
  if (channel.message_encoding != "cdr") return r;
  const auto schema = contents.schemas.find(channel.schema_id);
  if (schema == contents.schemas.end()) return r;
  const auto& type = schema->second.name;
  const auto& topic = channel.topic;
  r.robot = wire::robot_of_topic(topic);
  if (r.robot) {
    const auto id = *r.robot;
    if (topic == wire::proximity_topic(prefix, id) && type == wire::type_name(wire::MessageKind::proximity_frame)) {
      r.carries = Carries::frames;
      r.kind = wire::MessageKind::proximity_frame;
    } else if (topic == wire::decision_topic(prefix, id) && type == wire::type_name(wire::MessageKind::decision)) {
      r.carries = Carries::decisions;
      r.kind = wire::MessageKind::decision;
    } else if (topic == wire::plan_topic(prefix, id) && type == wire::type_name(wire::MessageKind::decision)) {
      r.carries = Carries::plans;
      r.kind = wire::MessageKind::decision;
    } else if (topic == wire::tracked_pose_topic(prefix, id)) {
      r.carries = Carries::tracked_poses;
    }
    return r;
  }
  if (topic == wire::arena_telemetry_topic(prefix) && type == wire::type_name(wire::MessageKind::arena_telemetry)) {
    r.carries = Carries::telemetry;
    r.kind = wire::MessageKind::arena_telemetry;
  } else if (topic == wire::agent_status_topic(prefix) && type == wire::type_name(wire::MessageKind::agent_status)) {
    r.carries = Carries::statuses;
    r.kind = wire::MessageKind::agent_status;
  } else if (topic == wire::poses_topic(prefix) && type == wire::type_name(wire::MessageKind::poses)) {
    r.carries = Carries::poses;
    r.kind = wire::MessageKind::poses;
  }
  return r;
}

const std::map<std::string, std::string>* find_metadata(const recording::McapContents& contents,
                                                         const std::string& name) {
  for (const auto& [n, m] : contents.metadata) {
    if (n == name) return &m;
  }
  return nullptr;
}

}  // namespace

Recording parse_recording(std::span<const std::byte> bytes, const std::string& name) {
  Recording out;
  out.path = name;
  // The channels' roles need the prefix, which is in the metadata the recorder writes first;
  // messages are kept as bytes until it is known (a file from another writer may put it later).
  struct Raw {
    std::uint16_t channel;
    std::uint64_t log_time, publish_time;
    std::vector<std::byte> data;
  };
  std::vector<Raw> raw;
  recording::McapContents contents;
  try {
    contents = recording::read_mcap(bytes, [&](const recording::McapChannel& c, const recording::McapMessage& m) {
      raw.push_back({c.id, m.log_time, m.publish_time, {m.data.begin(), m.data.end()}});
    });
  } catch (const recording::McapError& e) {
    throw RecordingError("'" + name + "': " + e.what());
  }
  const auto* meta = find_metadata(contents, "retreat");
  if (meta == nullptr || meta->count("config") == 0 || meta->count("prefix") == 0) {
    throw RecordingError("'" + name +
                         "': no 'retreat' metadata with the run's config and prefix: not a recording made by "
                         "retreat-record");
  }
  out.metadata = *meta;
  try {
    out.scenario = scenario::parse_json(meta->at("config"), name + ", metadata retreat.config");
  } catch (const std::exception& e) {
    throw RecordingError("'" + name + "': " + e.what());
  }
  if (const auto* r = find_metadata(contents, "retreat.recorder"); r != nullptr && r->count("dropped") > 0) {
    try {
      out.recorder_dropped = std::stoll(r->at("dropped"));
    } catch (const std::exception&) {
      throw RecordingError("'" + name + "': metadata retreat.recorder.dropped '" + r->at("dropped") +
                           "' is not a number");
    }
  }
  const auto& prefix = meta->at("prefix");
  std::map<std::uint16_t, ChannelRole> roles;
  for (const auto& [id, channel] : contents.channels) roles[id] = role_of(channel, contents, prefix);
  out.messages = raw.size();
  for (const auto& m : raw) {
    const auto& role = roles.at(m.channel);
    switch (role.carries) {
      case Carries::foreign:
        ++out.foreign;
        continue;
      case Carries::tracked_poses:
        ++out.tracked_poses;
        continue;
      default:
        break;
    }
    auto sample = transport::decode_serialized(role.kind, m.data);
    if (!sample) {
      ++out.undecodable;
      continue;
    }
    if (wire::validate(*sample, role.robot) != wire::SampleFault::ok) {
      ++out.invalid;
      continue;
    }
    switch (role.carries) {
      case Carries::frames:
        out.robots[*role.robot].frames.push_back(
            {std::get<wire::ProximityFrame>(*sample), m.log_time, m.publish_time});
        break;
      case Carries::decisions:
      case Carries::plans:
        // A recording holds one of the two (run.plans decides which the agents write).
        if ((role.carries == Carries::plans) != out.scenario.run.plans) {
          ++out.foreign;
          break;
        }
        out.robots[*role.robot].answers.push_back({std::get<wire::Decision>(*sample), m.log_time, m.publish_time});
        break;
      case Carries::telemetry:
        out.telemetry.push_back({std::get<wire::ArenaTelemetry>(*sample), m.log_time, m.publish_time});
        break;
      case Carries::statuses:
        out.statuses.push_back({std::get<wire::AgentStatus>(*sample), m.log_time, m.publish_time});
        break;
      case Carries::poses:
        out.poses.push_back({std::get<wire::Poses>(*sample), m.log_time, m.publish_time});
        break;
      default:
        break;
    }
  }
  return out;
}

Recording load_recording(const std::string& path) {
  const auto bytes = retreat::read_file(path);
  if (!bytes) throw RecordingError("'" + path + "': cannot read it as a file");
  return parse_recording(std::as_bytes(std::span(bytes->data(), bytes->size())), path);
}

}  // namespace retreat::replay
