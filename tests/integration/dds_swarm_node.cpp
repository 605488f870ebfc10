// Test and benchmark tool: one participant shaped like a retreat process, for the DDS profile
// tests (tests/integration/dds_profiles_test.cpp) and deploy/bench/discovery_scale.sh.
//
//   --role agent --robot i : like retreat-agent: user data "retreat:agent:robot=<i>", a reader on
//                            <prefix>/robot_<i>/proximity and a writer on
//                            <prefix>/robot_<i>/decision; answers every frame with a decision for
//                            the frame's tick. On exit prints participants=<number of participants
//                            it discovered>.
//   --role hub --agents N  : like retreat-arena: user data "retreat:arena", for robots
//                            first..first+N-1 a proximity writer and a decision reader. Waits until
//                            every one of them is matched, then sends frames (re-sent every second
//                            to robots that have not answered) until every agent answered once.
//                            Prints one result line (and writes it to --result):
//                              matched=<m>/<N> match_s=<s> matched_at_unix=<t> answered=<a>/<N>
//                              answer_s=<s> answered_at_unix=<t> participants=<p>
//                            Times are measured from the hub's start; *_at_unix are wall-clock
//                            stamps so that a script can measure from its own last agent start.
//
// Both roles stop on SIGTERM or SIGINT and, whatever happens, after --max-seconds: the tool never
// hangs. Exit codes: 0 done (hub: everything matched and answered), 1 failure or timeout,
// 2 bad arguments or unusable profile.

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <thread>
#include <vector>

#include "retreat/transport/factory.hpp"

namespace {

using namespace retreat;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t stop_requested = 0;
extern "C" void on_signal(int) { stop_requested = 1; }

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

struct Settings {
  std::string role, dds, profile, prefix = "retreat", result;
  int domain = 0;
  std::uint32_t robot = 0, first = 0, agents = 1;
  double max_seconds = 900, match_timeout = 120, answer_timeout = 60;
  bool linger = false;
};

int run_agent(const Settings& s, Clock::time_point start) {
  transport::ParticipantOptions options;
  options.domain_id = s.domain;
  options.name = "retreat-agent/robot_" + std::to_string(s.robot);
  options.user_data = "retreat:agent:robot=" + std::to_string(s.robot);
  options.profile = s.profile;
  auto t = transport::make_transport(s.dds, options);
  const auto q = transport::QosIntent::control();
  auto frames =
      t->create_reader<wire::ProximityFrame>({wire::proximity_topic(s.prefix, s.robot), q});
  auto decisions = t->create_writer<wire::Decision>({wire::decision_topic(s.prefix, s.robot), q});
  while (stop_requested == 0 && seconds_since(start) < s.max_seconds) {
    t->wait(200ms);
    for (const auto& f : frames.take()) {
      decisions.write({s.robot, f.tick, f.time, false});
    }
  }
  // What this agent discovered (itself included): in a star, only itself, the hub and the
  // hub's other clients that share a topic with it.
  std::printf("participants=%zu\n", t->participants().size());
  std::fflush(stdout);
  return 0;
}

int run_hub(const Settings& s, Clock::time_point start) {
  transport::ParticipantOptions options;
  options.domain_id = s.domain;
  options.name = "retreat-arena";
  options.user_data = "retreat:arena";
  options.profile = s.profile;
  auto t = transport::make_transport(s.dds, options);
  const auto q = transport::QosIntent::control();
  std::vector<transport::Writer<wire::ProximityFrame>> frames;
  std::vector<transport::Reader<wire::Decision>> decisions;
  for (std::uint32_t i = 0; i < s.agents; ++i) {
    frames.push_back(
        t->create_writer<wire::ProximityFrame>({wire::proximity_topic(s.prefix, s.first + i), q}));
    decisions.push_back(
        t->create_reader<wire::Decision>({wire::decision_topic(s.prefix, s.first + i), q}));
  }

  // Phase 1: discovery. A robot counts as matched when its frame writer and its decision reader
  // each have at least one remote endpoint.
  std::size_t matched = 0;
  double match_s = -1, matched_at = 0;
  const auto count_matched = [&] {
    std::size_t n = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      n += frames[i].matched_count() > 0 && decisions[i].matched_count() > 0;
    }
    return n;
  };
  while (stop_requested == 0 && seconds_since(start) < std::min(s.match_timeout, s.max_seconds)) {
    matched = count_matched();
    if (matched == frames.size()) {
      match_s = seconds_since(start);
      matched_at = unix_now();
      break;
    }
    std::this_thread::sleep_for(20ms);
  }

  // Phase 2: delivery. Only a received answer proves that both directions work (a match alone
  // does not: Fast DDS reports matches the remote side rejected).
  std::vector<bool> answered(frames.size(), false);
  std::size_t n_answered = 0;
  double answer_s = -1, answered_at = 0;
  if (match_s >= 0) {
    const auto phase_start = Clock::now();
    auto next_send = Clock::now();
    std::int64_t tick = 0;
    while (stop_requested == 0 && seconds_since(phase_start) < s.answer_timeout &&
           seconds_since(start) < s.max_seconds) {
      if (Clock::now() >= next_send) {
        for (std::size_t i = 0; i < frames.size(); ++i) {
          if (!answered[i]) {
            frames[i].write({s.first + static_cast<std::uint32_t>(i), tick,
                             0.1 * static_cast<double>(tick), wire::Phase::inside, false, 0});
          }
        }
        ++tick;
        next_send = Clock::now() + 1s;
      }
      t->wait(50ms);
      for (std::size_t i = 0; i < decisions.size(); ++i) {
        if (!decisions[i].take().empty() && !answered[i]) {
          answered[i] = true;
          ++n_answered;
        }
      }
      if (n_answered == frames.size()) {
        answer_s = seconds_since(start);
        answered_at = unix_now();
        break;
      }
    }
  }

  char line[512];
  std::snprintf(line, sizeof line,
                "matched=%zu/%zu match_s=%.3f matched_at_unix=%.3f answered=%zu/%zu answer_s=%.3f "
                "answered_at_unix=%.3f participants=%zu\n",
                matched, frames.size(), match_s, matched_at, n_answered, frames.size(), answer_s,
                answered_at, t->participants().size());
  std::fputs(line, stdout);
  std::fflush(stdout);
  if (!s.result.empty()) {
    const std::string tmp = s.result + ".tmp";
    std::ofstream(tmp) << line;
    std::rename(tmp.c_str(), s.result.c_str());
  }
  const int code = n_answered == frames.size() ? 0 : 1;
  while (s.linger && stop_requested == 0 && seconds_since(start) < s.max_seconds) {
    std::this_thread::sleep_for(100ms);
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  const auto start = Clock::now();
  Settings s;
  CLI::App app{"retreat DDS swarm node (test and benchmark tool)"};
  app.add_option("--role", s.role, "hub or agent")
      ->required()
      ->check(CLI::IsMember({"hub", "agent"}));
  app.add_option("--dds", s.dds, "fastdds or cyclonedds")->required();
  app.add_option("--profile", s.profile,
                 "vendor XML profile (empty: the adapter's loopback default)");
  app.add_option("--domain", s.domain, "DDS domain id")->required();
  app.add_option("--prefix", s.prefix, "topic prefix");
  app.add_option("--robot", s.robot, "agent: robot id");
  app.add_option("--agents", s.agents, "hub: number of robots")->check(CLI::PositiveNumber);
  app.add_option("--first-robot", s.first, "hub: first robot id");
  app.add_option("--match-timeout", s.match_timeout, "hub: seconds to wait for discovery");
  app.add_option("--answer-timeout", s.answer_timeout, "hub: seconds to wait for every answer");
  app.add_option("--result", s.result, "hub: file to write the result line to");
  app.add_flag("--linger", s.linger, "hub: keep running after the result until stopped");
  app.add_option("--max-seconds", s.max_seconds, "exit after this many seconds whatever happens")
      ->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  try {
    return s.role == "hub" ? run_hub(s, start) : run_agent(s, start);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "retreat_dds_swarm_node: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat_dds_swarm_node: %s\n", e.what());
    return 1;
  }
}
