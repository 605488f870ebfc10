// retreat_scripted_swarm: what an arena and N agents publish for observers, scripted, so that the
// bridge and its page can be tried with swarms larger than this machine can run as processes
// (the dashboard test with 1,000 robots, deploy/bench/bridge_page.sh). Only the observation
// topics, as the arena and the agents write them: telemetry and poses HZ times a second, and each
// robot's status once a second (spread over the second). Robots circle their places on a grid
// at the density of kinetic-1000.yaml, and carry or not by turns. Nothing here is the model:
// the numbers only have to move.
//
//   retreat_scripted_swarm VENDOR DOMAIN ROBOTS HZ SECONDS [PREFIX]
//
// PREFIX is the topic prefix (dds.prefix; default retreat).
// Waits (up to 120 s) until a reader has matched each writer, publishes for SECONDS, waits for
// every sample to be acknowledged, and prints one JSON line: the samples written per topic.
// Exit 0, or 1 when nobody matched, 2 on bad arguments.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "retreat/transport/factory.hpp"
#include "retreat/wire/messages.hpp"
#include "retreat/wire/topics.hpp"

namespace {

using namespace std::chrono_literals;
using namespace retreat;

long number(const char* text, long low, long high, const char* what) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < low || v > high) {
    std::fprintf(stderr, "retreat_scripted_swarm: %s '%s': a whole number in [%ld, %ld]\n", what, text, low, high);
    std::exit(2);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 6 && argc != 7) {
    std::fprintf(stderr, "usage: retreat_scripted_swarm VENDOR DOMAIN ROBOTS HZ SECONDS [PREFIX]\n");
    return 2;
  }
  const std::string vendor = argv[1];
  const auto domain = static_cast<int>(number(argv[2], 0, 232, "DOMAIN"));
  const auto robots = static_cast<std::uint32_t>(number(argv[3], 1, 100000, "ROBOTS"));
  const auto hz = static_cast<int>(number(argv[4], 1, 100, "HZ"));
  const auto seconds = number(argv[5], 1, 3600, "SECONDS");

  auto t = transport::make_transport(vendor, {domain, "scripted-swarm", "", ""});
  const std::string prefix = argc == 7 ? argv[6] : "retreat";
  auto telemetry = t->create_writer<wire::ArenaTelemetry>({wire::arena_telemetry_topic(prefix), transport::QosIntent::state()});
  auto poses = t->create_writer<wire::Poses>({wire::poses_topic(prefix), transport::QosIntent::state()});
  auto statuses = t->create_writer<wire::AgentStatus>({wire::agent_status_topic(prefix), transport::QosIntent::state()});
  const auto give_up = std::chrono::steady_clock::now() + 120s;
  while (telemetry.matched_count() == 0 || poses.matched_count() == 0 || statuses.matched_count() == 0) {
    if (std::chrono::steady_clock::now() > give_up) {
      std::fprintf(stderr, "retreat_scripted_swarm: no reader matched within 120 s\n");
      return 1;
    }
    std::this_thread::sleep_for(20ms);
  }

  // kinetic-1000.yaml's density, 1.6 robots/m², on a square grid.
  const double side = std::sqrt(robots / 1.6);
  const auto per_row = static_cast<std::uint32_t>(std::ceil(std::sqrt(static_cast<double>(robots))));
  const double spacing = side / per_row;
  const double dt = 1.0 / hz;
  const auto ticks = static_cast<std::int64_t>(seconds) * hz;
  std::uint64_t written[3] = {0, 0, 0};
  wire::Poses p;
  p.robots.resize(robots);
  p.pickups = {{static_cast<float>(-side / 4), 0.0f}};
  p.dropoffs = {{static_cast<float>(side / 4), 0.0f}};
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t k = 0; k < ticks; ++k) {
    const double time = static_cast<double>(k) * dt;
    std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                              std::chrono::duration<double>(time)));
    for (std::uint32_t i = 0; i < robots; ++i) {
      const double cx = -side / 2 + spacing * (i % per_row + 0.5);
      const double cy = -side / 2 + spacing * (i / per_row + 0.5);
      const double w = 0.5 + 0.5 * (i % 7) / 7.0;  // rad/s
      const double a = w * time + i;
      auto& r = p.robots[i];
      r.robot_id = i;
      r.x = static_cast<float>(cx + 0.3 * spacing * std::cos(a));
      r.y = static_cast<float>(cy + 0.3 * spacing * std::sin(a));
      r.theta = static_cast<float>(a + M_PI / 2);
      r.phase = wire::Phase::inside;
      r.loaded = static_cast<long>(time / 5.0 + i) % 2 == 0;
    }
    p.tick = k;
    p.time = time;
    if (poses.write(p) == transport::WriteResult::ok) ++written[1];
    wire::ArenaTelemetry m;
    m.tick = k;
    m.time = time;
    m.inside = robots;
    m.true_density = 1.6;
    m.deliveries = static_cast<std::uint64_t>(time * robots / 50.0);
    m.ticks_per_second = hz;
    if (telemetry.write(m) == transport::WriteResult::ok) ++written[0];
    for (std::uint32_t i = static_cast<std::uint32_t>(k % hz); i < robots; i += static_cast<std::uint32_t>(hz)) {
      wire::AgentStatus s;
      s.robot_id = i;
      s.tick = k;
      s.time = time;
      s.deciding = time > 2.0;
      s.onsets_in_window = static_cast<std::uint32_t>((i + k) % 9);
      s.lambda_hat = 1.6 * (1.0 + 0.4 * std::sin(0.1 * time + i));
      s.epsilon = 0.001 * (i % 10);
      if (statuses.write(s) == transport::WriteResult::ok) ++written[2];
    }
  }
  const bool acknowledged = telemetry.wait_for_acknowledgments(30s) && poses.wait_for_acknowledgments(30s) &&
                            statuses.wait_for_acknowledgments(30s);
  std::printf("{\"telemetry\": %llu, \"poses\": %llu, \"statuses\": %llu, \"acknowledged\": %s}\n",
              static_cast<unsigned long long>(written[0]), static_cast<unsigned long long>(written[1]),
              static_cast<unsigned long long>(written[2]), acknowledged ? "true" : "false");
  return 0;
}
