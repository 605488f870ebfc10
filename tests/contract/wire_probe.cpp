// Test tool for the cross-vendor suite. As a writer it publishes `count` deterministic samples
// of every message kind; as a reader it receives them and checks every field of every sample
// and their order. Exit code 0 = all identical, 1 = mismatch or loss, 2 = bad arguments.
//
// Reads/writes: <prefix>/robot_5/proximity, <prefix>/robot_5/decision, <prefix>/agent_status,
// <prefix>/arena_telemetry, <prefix>/poses (all reliable, volatile, keep all).

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "retreat/testing/process.hpp"
#include "retreat/testing/samples.hpp"
#include "retreat/transport/factory.hpp"

namespace {

using namespace retreat;
using namespace std::chrono_literals;

struct Topics {
  std::string frame, decision, status, telemetry, poses;
};

template <class M, class Make>
bool check(const std::vector<M>& got, int count, Make make, const char* what) {
  if (got.size() != static_cast<std::size_t>(count)) {
    std::fprintf(stderr, "%s: received %zu of %d\n", what, got.size(), count);
    return false;
  }
  for (int i = 0; i < count; ++i) {
    if (!(got[static_cast<std::size_t>(i)] == make(i))) {
      std::fprintf(stderr, "%s: sample %d differs\n", what, i);
      return false;
    }
  }
  return true;
}

/// @p ready: the file the reader creates once every one of its readers is matched (empty: none).
int run_writer(transport::Transport& t, const Topics& topics, int count, const std::string& ready) {
  const auto q = transport::QosIntent::control();
  auto frames = t.create_writer<wire::ProximityFrame>({topics.frame, q});
  auto decisions = t.create_writer<wire::Decision>({topics.decision, q});
  auto statuses = t.create_writer<wire::AgentStatus>({topics.status, q});
  auto telemetry = t.create_writer<wire::ArenaTelemetry>({topics.telemetry, q});
  auto poses = t.create_writer<wire::Poses>({topics.poses, q});
  const auto deadline = std::chrono::steady_clock::now() + retreat::testing::hang_ceiling;
  // Both sides must have matched before the first sample: a volatile reader that matches the
  // writer late never gets the earlier samples, though the writer sees them acknowledged (a
  // wall-clock pause here failed under load). The writer's matches, then the reader's file.
  while (frames.matched_count() == 0 || decisions.matched_count() == 0 ||
         statuses.matched_count() == 0 || telemetry.matched_count() == 0 ||
         poses.matched_count() == 0 || (!ready.empty() && !std::filesystem::exists(ready))) {
    if (std::chrono::steady_clock::now() > deadline) {
      std::fprintf(stderr, "writer: the reader did not match within the ceiling\n");
      return 1;
    }
    std::this_thread::sleep_for(10ms);
  }
  for (int i = 0; i < count; ++i) {
    if (frames.write(testing::frame_sample(5, i)) != transport::WriteResult::ok ||
        decisions.write(testing::decision_sample(5, i)) != transport::WriteResult::ok ||
        statuses.write(testing::status_sample(5, i)) != transport::WriteResult::ok ||
        telemetry.write(testing::telemetry_sample(0, i)) != transport::WriteResult::ok ||
        poses.write(testing::poses_sample(0, i)) != transport::WriteResult::ok) {
      std::fprintf(stderr, "writer: write %d failed\n", i);
      return 1;
    }
  }
  const bool acked = frames.wait_for_acknowledgments(retreat::testing::hang_ceiling) && decisions.wait_for_acknowledgments(retreat::testing::hang_ceiling) &&
                     statuses.wait_for_acknowledgments(retreat::testing::hang_ceiling) && telemetry.wait_for_acknowledgments(retreat::testing::hang_ceiling) &&
                     poses.wait_for_acknowledgments(retreat::testing::hang_ceiling);
  std::printf("writer: wrote %d samples of each kind, acknowledged: %s\n", count, acked ? "yes" : "no");
  return acked ? 0 : 1;
}

/// @p ready: created once every reader is matched, for the writer (empty: none).
int run_reader(transport::Transport& t, const Topics& topics, int count, const std::string& ready) {
  const auto q = transport::QosIntent::control();
  auto frames = t.create_reader<wire::ProximityFrame>({topics.frame, q});
  auto decisions = t.create_reader<wire::Decision>({topics.decision, q});
  auto statuses = t.create_reader<wire::AgentStatus>({topics.status, q});
  auto telemetry = t.create_reader<wire::ArenaTelemetry>({topics.telemetry, q});
  auto poses = t.create_reader<wire::Poses>({topics.poses, q});
  std::vector<wire::ProximityFrame> f;
  std::vector<wire::Decision> d;
  std::vector<wire::AgentStatus> s;
  std::vector<wire::ArenaTelemetry> a;
  std::vector<wire::Poses> p;
  const auto n = static_cast<std::size_t>(count);
  const auto deadline = std::chrono::steady_clock::now() + retreat::testing::hang_ceiling;
  while (!ready.empty() && (frames.matched_count() == 0 || decisions.matched_count() == 0 ||
                            statuses.matched_count() == 0 || telemetry.matched_count() == 0 ||
                            poses.matched_count() == 0)) {
    if (std::chrono::steady_clock::now() > deadline) break;
    std::this_thread::sleep_for(10ms);
  }
  if (!ready.empty()) std::ofstream(ready) << "matched\n";
  while ((f.size() < n || d.size() < n || s.size() < n || a.size() < n || p.size() < n) &&
         std::chrono::steady_clock::now() < deadline) {
    t.wait(50ms);
    for (auto& m : frames.take()) f.push_back(m);
    for (auto& m : decisions.take()) d.push_back(m);
    for (auto& m : statuses.take()) s.push_back(m);
    for (auto& m : telemetry.take()) a.push_back(m);
    for (auto& m : poses.take()) p.push_back(std::move(m));
  }
  bool ok = check(f, count, [](int i) { return testing::frame_sample(5, i); }, "ProximityFrame");
  ok = check(d, count, [](int i) { return testing::decision_sample(5, i); }, "Decision") && ok;
  ok = check(s, count, [](int i) { return testing::status_sample(5, i); }, "AgentStatus") && ok;
  ok = check(a, count, [](int i) { return testing::telemetry_sample(0, i); }, "ArenaTelemetry") && ok;
  ok = check(p, count, [](int i) { return testing::poses_sample(0, i); }, "Poses") && ok;
  std::printf("reader: %s\n", ok ? "all samples identical and in order" : "MISMATCH");
  // Stay a moment so that the writer receives our final acknowledgements before we leave.
  std::this_thread::sleep_for(1s);
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"retreat wire probe (test tool)"};
  std::string role, dds, prefix = "probe";
  int domain = 0, count = 1000;
  app.add_option("--role", role, "writer or reader")->required()->check(CLI::IsMember({"writer", "reader"}));
  app.add_option("--dds", dds, "vendor")->required();
  app.add_option("--domain", domain, "DDS domain id")->required();
  app.add_option("--prefix", prefix, "topic prefix");
  app.add_option("--count", count, "samples per kind")->check(CLI::PositiveNumber);
  std::string ready;
  app.add_option("--ready", ready, "a file the reader creates once matched and the writer waits for");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    transport::ParticipantOptions options;
    options.domain_id = domain;
    options.name = "wire-probe-" + role;
    auto t = transport::make_transport(dds, options);
    const Topics topics{wire::proximity_topic(prefix, 5), wire::decision_topic(prefix, 5),
                        wire::agent_status_topic(prefix), wire::arena_telemetry_topic(prefix),
                        wire::poses_topic(prefix)};
    return role == "writer" ? run_writer(*t, topics, count, ready) : run_reader(*t, topics, count, ready);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "retreat_wire_probe: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat_wire_probe: %s\n", e.what());
    return 1;
  }
}
