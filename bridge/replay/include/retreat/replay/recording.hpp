#pragma once
/// @file
/// A recording made by retreat-record, read back: the run's scenario from the file's metadata and
/// every robot's frames and answers, the telemetry and the agents' statuses, decoded with a DDS
/// vendor's generated code and validated as a reader on the wire would. The tools that read
/// recordings (retreat-replay, retreat-diff) start here.

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/scenario/params.hpp"
#include "retreat/wire/messages.hpp"

namespace retreat::replay {

/// A file that is not a readable recording of a retreat run; the message is one line.
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One sample as recorded.
template <class M>
struct Recorded {
  M sample;
  std::uint64_t log_time = 0;      ///< the recorder's clock [ns]
  std::uint64_t publish_time = 0;  ///< the writer's source timestamp [ns]
};

/// What one robot's agent heard and said, in the order the recorder took it.
struct RecordedRobot {
  std::vector<Recorded<wire::ProximityFrame>> frames;  ///< every frame, re-sends included
  std::vector<Recorded<wire::Decision>> answers;       ///< decisions, or plans with run.plans
};

struct Recording {
  std::string path;
  scenario::Scenario scenario;                   ///< the run's resolved scenario (metadata `retreat`.config)
  std::map<std::string, std::string> metadata;   ///< the `retreat` metadata record
  std::map<std::uint32_t, RecordedRobot> robots;  ///< by robot id
  std::vector<Recorded<wire::ArenaTelemetry>> telemetry;
  std::vector<Recorded<wire::AgentStatus>> statuses;
  std::vector<Recorded<wire::Poses>> poses;  ///< the arena's (display only)
  std::uint64_t messages = 0;     ///< messages in the file
  std::uint64_t tracked_poses = 0;  ///< real robots' tracked poses (counted, not decoded)
  std::uint64_t foreign = 0;      ///< messages on channels that are not the run's topics (ignored)
  std::uint64_t undecodable = 0;  ///< the run's messages that did not decode (dropped, counted)
  std::uint64_t invalid = 0;      ///< decoded but invalid on the wire (wire::validate; dropped, counted)
  std::int64_t recorder_dropped = -1;  ///< samples the recorder lost (metadata `retreat.recorder`; -1: absent)
};

/// Reads a recording. @throws RecordingError (one line naming the path): not MCAP, truncated or
/// corrupted (recording::McapError's line), no `retreat` metadata, a config that is not a valid
/// scenario.
Recording load_recording(const std::string& path);

/// The same from the file's bytes; @p name stands for the path in errors.
Recording parse_recording(std::span<const std::byte> bytes, const std::string& name);

}  // namespace retreat::replay
