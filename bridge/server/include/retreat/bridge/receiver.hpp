#pragma once
/// @file
/// The bridge's only DDS endpoints: readers of `<prefix>/arena_telemetry`, `<prefix>/poses` and
/// `<prefix>/agent_status` (transient-local, keep last 1, so a late bridge gets the current state
/// at once). Never a robot's own topics. Samples are taken on the thread that calls run().

#include <array>
#include <atomic>
#include <chrono>
#include <fstream>
#include <functional>
#include <memory>
#include <string>

#include "retreat/bridge/live_state.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::bridge {

/// Appends every agent status the bridge receives to `<dir>/agent_status.csv` (the estimates
/// over time that the report plots; the arena's files do not have them).
class StatusRecorder {
 public:
  /// @throws std::runtime_error when the file cannot be written.
  explicit StatusRecorder(const std::string& dir);
  void record(const wire::AgentStatus& s);
  void flush();
  static constexpr const char* file_name = "agent_status.csv";

 private:
  std::ofstream out_;
};

class Receiver {
 public:
  /// Creates the three readers on `transport` (which must outlive this).
  Receiver(transport::Transport& transport, const std::string& prefix, LiveState& state,
           StatusRecorder* recorder = nullptr);

  /// Takes what has arrived and feeds it to the state; returns the number of samples taken.
  std::size_t poll();
  /// Waits for samples and takes them until `stop` is set; `tick` runs about every 200 ms
  /// (e.g. to look for the end of the run).
  void run(const std::atomic<bool>& stop, const std::function<void()>& tick = {});

  /// Samples the readers dropped as invalid or undecodable (as of the last poll; any thread).
  std::uint64_t dropped() const { return dropped_.load(); }
  /// Remote writers matched with the telemetry, poses and status readers (as of the last
  /// run() tick; any thread).
  std::array<std::size_t, 3> matched() const {
    return {matched_[0].load(), matched_[1].load(), matched_[2].load()};
  }

 private:
  void refresh_counters();

  transport::Transport& transport_;
  LiveState& state_;
  StatusRecorder* recorder_;
  transport::Reader<wire::ArenaTelemetry> telemetry_;
  transport::Reader<wire::Poses> poses_;
  transport::Reader<wire::AgentStatus> statuses_;
  std::atomic<std::uint64_t> dropped_{0};
  std::array<std::atomic<std::size_t>, 3> matched_{};
};

}  // namespace retreat::bridge
