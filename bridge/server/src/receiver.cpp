#include "retreat/bridge/receiver.hpp"

#include <filesystem>
#include <stdexcept>

#include "retreat/core/paths.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::bridge {

using namespace std::chrono_literals;

namespace {

constexpr const char* header =
    "time,robot,tick,deciding,retreating,onsets_in_window,lambda_hat,epsilon\n";

/// Bytes of `path` up to and including its last newline if it begins with the header; 0 if it
/// does not exist, is empty or holds something else (then it is rewritten).
std::size_t complete_rows_size(const std::string& path) {
  const auto read = retreat::read_file(path);
  if (!read) return 0;
  const std::string& text = *read;
  if (text.rfind(header, 0) != 0) return 0;
  return text.rfind('\n') + 1;
}

}  // namespace

StatusRecorder::StatusRecorder(const std::string& dir) {
  const auto path = dir + "/" + file_name;
  // A restarted bridge (retreat-launch restarts one that died) continues the record: it drops
  // a row the dead one left half written and appends after the last complete one.
  const std::size_t complete = complete_rows_size(path);
  if (complete > 0) std::filesystem::resize_file(path, complete);
  out_.open(path, std::ios::out | (complete > 0 ? std::ios::app : std::ios::trunc));
  if (!out_) throw std::runtime_error("--out '" + dir + "': cannot write " + file_name);
  if (complete == 0) out_ << header;
  out_.precision(9);
}

void StatusRecorder::record(const wire::AgentStatus& s) {
  out_ << s.time << ',' << s.robot_id << ',' << s.tick << ',' << (s.deciding ? 1 : 0) << ','
       << (s.retreating ? 1 : 0) << ',' << s.onsets_in_window << ',' << s.lambda_hat << ','
       << s.epsilon << '\n';
}

void StatusRecorder::flush() { out_.flush(); }

Receiver::Receiver(transport::Transport& transport, const std::string& prefix, LiveState& state,
                   StatusRecorder* recorder)
    : transport_(transport),
      state_(state),
      recorder_(recorder),
      telemetry_(transport.create_reader<wire::ArenaTelemetry>(
          {wire::arena_telemetry_topic(prefix), transport::QosIntent::state()})),
      poses_(transport.create_reader<wire::Poses>({wire::poses_topic(prefix), transport::QosIntent::state()})),
      statuses_(transport.create_reader<wire::AgentStatus>(
          {wire::agent_status_topic(prefix), transport::QosIntent::state()})) {}

std::size_t Receiver::poll() {
  auto t = telemetry_.take();
  auto p = poses_.take();
  auto s = statuses_.take();
  const std::size_t n = t.size() + p.size() + s.size();
  if (n == 0) return 0;
  if (recorder_ != nullptr) {
    for (const auto& status : s) recorder_->record(status);
  }
  state_.update([&](telemetry::Aggregator& a) {
    // Statuses and poses first: a telemetry sample appends a history point with the estimates
    // known at that moment.
    for (const auto& status : s) a.on_status(status);
    for (const auto& poses : p) a.on_poses(poses);
    for (const auto& telemetry : t) a.on_telemetry(telemetry);
  });
  return n;
}

void Receiver::run(const std::atomic<bool>& stop, const std::function<void()>& tick) {
  auto next_tick = std::chrono::steady_clock::now();
  while (!stop.load()) {
    transport_.wait(50ms);
    poll();
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_tick) {
      next_tick = now + 200ms;
      if (recorder_ != nullptr) recorder_->flush();
      refresh_counters();
      if (tick) tick();
    }
  }
  poll();
  refresh_counters();
  if (recorder_ != nullptr) recorder_->flush();
}

void Receiver::refresh_counters() {
  dropped_.store(telemetry_.stats().dropped_total() + poses_.stats().dropped_total() +
                 statuses_.stats().dropped_total());
  matched_[0].store(telemetry_.matched_count());
  matched_[1].store(poses_.matched_count());
  matched_[2].store(statuses_.matched_count());
}

}  // namespace retreat::bridge
