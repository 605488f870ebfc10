// No inter-robot communication, checked in DDS discovery of a running swarm.
//
// The Transport API reports only our own endpoints' matches, so the test makes itself a peer of
// every endpoint an agent could have on the contract's topics: on each robot topic and each
// shared topic it creates a reader (best effort, volatile: matches any writer) and a writer
// (reliable, transient local: matches any reader) that never writes. Whatever an agent reads or
// writes on those topics is then matched with us, and participants() names the agent by its
// user data `retreat:agent:robot=<id>`. The test fails if
//   - an agent has a reader on any topic but its own robot's proximity topic,
//   - an agent has a writer on any topic but its own robot's decision topic and agent_status,
//   - anything but the arena writes a robot's proximity topic (the only writer an agent's
//     reader may be matched to), or anything but the arena reads a robot's decision topic,
// and it checks that every agent is seen on its own topics. It runs once with a Fast DDS and
// once with a Cyclone DDS observer, each during its own mixed swarm (agents of both vendors).
// One observer per test process: a Fast DDS participant next to a Cyclone DDS participant on
// the same domain in one process trips an assertion in Fast DDS 2.9.1's statistics module
// (OutputTrafficManager::set_statistics_message_data) and aborts.
// Topics outside the contract cannot be seen this way; no program creates any.

#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <set>
#include <thread>

#include "retreat/testing/domains.hpp"
#include "launch_support.hpp"

namespace retreat::launch_test {
namespace {

// Domain ids of this file: 56 (Fast DDS observer), 60 (Cyclone DDS observer).
constexpr std::uint32_t robots = 12;

constexpr transport::QosIntent match_any_writer{transport::Reliability::best_effort,
                                                transport::Durability::volatile_data, 1};
constexpr transport::QosIntent match_any_reader{transport::Reliability::reliable,
                                                transport::Durability::transient_local, 1};

/// A participant with a silent reader and writer on every topic of the contract.
class Observer {
 public:
  Observer(const std::string& vendor, int domain)
      : t_(transport::make_transport(vendor, {domain, "launch-isolation-observer", "retreat:observer", ""})) {
    const std::string p = "retreat";
    for (std::uint32_t r = 0; r < robots; ++r) {
      proximity_readers_.push_back(t_->create_reader<wire::ProximityFrame>({wire::proximity_topic(p, r), match_any_writer}));
      proximity_writers_.push_back(t_->create_writer<wire::ProximityFrame>({wire::proximity_topic(p, r), match_any_reader}));
      decision_readers_.push_back(t_->create_reader<wire::Decision>({wire::decision_topic(p, r), match_any_writer}));
      decision_writers_.push_back(t_->create_writer<wire::Decision>({wire::decision_topic(p, r), match_any_reader}));
    }
    status_reader_.emplace(t_->create_reader<wire::AgentStatus>({wire::agent_status_topic(p), match_any_writer}));
    status_writer_.emplace(t_->create_writer<wire::AgentStatus>({wire::agent_status_topic(p), match_any_reader}));
    telemetry_reader_.emplace(t_->create_reader<wire::ArenaTelemetry>({wire::arena_telemetry_topic(p), match_any_writer}));
    telemetry_writer_.emplace(t_->create_writer<wire::ArenaTelemetry>({wire::arena_telemetry_topic(p), match_any_reader}));
    poses_reader_.emplace(t_->create_reader<wire::Poses>({wire::poses_topic(p), match_any_writer}));
    poses_writer_.emplace(t_->create_writer<wire::Poses>({wire::poses_topic(p), match_any_reader}));
  }

  /// Who each remote participant is (its user data), by participant GUID.
  std::map<std::string, std::string> who() const {
    std::map<std::string, std::string> out;
    for (const auto& p : t_->participants()) out[p.guid] = p.user_data;
    return out;
  }
  std::vector<transport::EndpointMatches> matches() const { return t_->matched_endpoints(); }
  /// Drops received samples (our readers are best effort; nothing must pile up).
  void drain() {
    for (auto& r : proximity_readers_) r.take();
    for (auto& r : decision_readers_) r.take();
    status_reader_->take();
    telemetry_reader_->take();
    poses_reader_->take();
  }

 private:
  std::unique_ptr<transport::Transport> t_;
  std::vector<transport::Reader<wire::ProximityFrame>> proximity_readers_;
  std::vector<transport::Writer<wire::ProximityFrame>> proximity_writers_;
  std::vector<transport::Reader<wire::Decision>> decision_readers_;
  std::vector<transport::Writer<wire::Decision>> decision_writers_;
  std::optional<transport::Reader<wire::AgentStatus>> status_reader_;
  std::optional<transport::Writer<wire::AgentStatus>> status_writer_;
  std::optional<transport::Reader<wire::ArenaTelemetry>> telemetry_reader_;
  std::optional<transport::Writer<wire::ArenaTelemetry>> telemetry_writer_;
  std::optional<transport::Reader<wire::Poses>> poses_reader_;
  std::optional<transport::Writer<wire::Poses>> poses_writer_;
};

/// The robot id in "retreat:agent:robot=<id>", or -1 for any other participant.
long agent_robot(const std::string& user_data) {
  const std::string tag = "retreat:agent:robot=";
  if (user_data.rfind(tag, 0) != 0) return -1;
  return std::stol(user_data.substr(tag.size()));
}

/// What one observer saw: who is matched with our endpoint on each topic (remote user data).
struct Seen {
  std::map<std::string, std::set<std::string>> readers;  ///< topic -> remote readers (of our writer)
  std::map<std::string, std::set<std::string>> writers;  ///< topic -> remote writers (of our reader)
  std::set<std::string> unnamed;                         ///< matched participants not (yet) in discovery
};

Seen look(const Observer& o) {
  const auto who = o.who();
  Seen s;
  for (const auto& e : o.matches()) {
    auto& side = e.is_reader ? s.writers[e.topic] : s.readers[e.topic];
    for (const auto& r : e.remotes) {
      const auto it = who.find(r.participant_guid);
      if (it == who.end()) {
        s.unnamed.insert(r.participant_guid);
      } else if (it->second != "retreat:observer") {  // ourselves, and the other observer
        side.insert(it->second);
      }
    }
  }
  return s;
}

/// Every agent matched on its own proximity (as reader) and decision (as writer) topics, the
/// arena on every robot topic, and every matched participant known by its user data.
bool complete(const Seen& s) {
  if (!s.unnamed.empty()) return false;
  for (std::uint32_t r = 0; r < robots; ++r) {
    const auto agent = "retreat:agent:robot=" + std::to_string(r);
    const auto prox = wire::proximity_topic("retreat", r), dec = wire::decision_topic("retreat", r);
    if (!s.readers.count(prox) || !s.readers.at(prox).count(agent)) return false;
    if (!s.writers.count(dec) || !s.writers.at(dec).count(agent)) return false;
    if (!s.writers.count(prox) || !s.writers.at(prox).count("retreat:arena")) return false;
    if (!s.readers.count(dec) || !s.readers.at(dec).count("retreat:arena")) return false;
  }
  return true;
}

std::string set_text(const std::set<std::string>& items) {
  std::string out = "{";
  for (const auto& i : items) out += (out.size() > 1 ? ", " : "") + i;
  return out + "}";
}

/// Every isolation rule broken in what an observer saw, one line each (empty: isolated).
std::vector<std::string> violations(const Seen& s) {
  std::vector<std::string> out;
  const std::string status = wire::agent_status_topic("retreat");
  for (const auto& [topic, remotes] : s.readers) {
    for (const auto& who : remotes) {
      const long robot = agent_robot(who);
      if (robot >= 0 && topic != wire::proximity_topic("retreat", static_cast<wire::RobotId>(robot))) {
        out.push_back(who + " reads " + topic);
      }
    }
  }
  for (const auto& [topic, remotes] : s.writers) {
    for (const auto& who : remotes) {
      const long robot = agent_robot(who);
      if (robot >= 0 && topic != wire::decision_topic("retreat", static_cast<wire::RobotId>(robot)) && topic != status) {
        out.push_back(who + " writes " + topic);
      }
    }
  }
  const auto at = [](const std::map<std::string, std::set<std::string>>& m, const std::string& topic) {
    const auto it = m.find(topic);
    return it == m.end() ? std::set<std::string>{} : it->second;
  };
  for (std::uint32_t r = 0; r < robots; ++r) {
    const auto prox = wire::proximity_topic("retreat", r), dec = wire::decision_topic("retreat", r);
    const std::set<std::string> arena{"retreat:arena"}, agent{"retreat:agent:robot=" + std::to_string(r)};
    // The arena is the only writer an agent's proximity reader may be matched to (besides the
    // observer), and the only reader of its decisions.
    if (at(s.writers, prox) != arena) out.push_back(prox + " is written by " + set_text(at(s.writers, prox)));
    if (at(s.readers, prox) != agent) out.push_back(prox + " is read by " + set_text(at(s.readers, prox)));
    if (at(s.writers, dec) != agent) out.push_back(dec + " is written by " + set_text(at(s.writers, dec)));
    if (at(s.readers, dec) != arena) out.push_back(dec + " is read by " + set_text(at(s.readers, dec)));
  }
  // Every agent publishes its status; nobody but agents does.
  std::set<std::string> status_writers;
  for (std::uint32_t r = 0; r < robots; ++r) status_writers.insert("retreat:agent:robot=" + std::to_string(r));
  if (at(s.writers, status) != status_writers) {
    out.push_back(status + " is written by " + set_text(at(s.writers, status)));
  }
  return out;
}

std::string lines(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += "\n  " + i;
  return out;
}

struct ObserverCase {
  const char* vendor;
  int domain;
};

void PrintTo(const ObserverCase& c, std::ostream* os) { *os << c.vendor << " observer on domain " << c.domain; }

class LaunchIsolation : public ::testing::TestWithParam<ObserverCase> {};

TEST_P(LaunchIsolation, EveryAgentIsMatchedOnlyWithItsOwnRobotsTopicsInARunningSwarm) {
  if (!built("fastdds") || !built("cyclonedds")) GTEST_SKIP() << "needs both vendors";
  const auto [vendor, domain] = GetParam();
  const auto dir = fresh_dir(std::string("isolation-") + vendor);
  // A mixed swarm (agents of both vendors, a Cyclone arena) that does not end by itself (10^6
  // simulated s, hours of wall time even on a quiet machine): it is stopped (SIGTERM to the
  // launcher) once it has been looked at, however slow the machine made the looking. K_p = λ_in
  // = 0 makes ε ≡ 0: no robot retreats, so every agent is still there whenever the test looks.
  auto l = start_launch(dir, {robotarium, "--dds", "mixed", "--domain", std::to_string(domain), "--set",
                              "agent.K_p=0", "--set", "agent.lambda_in=0", "--set", "run.duration=1000000"});
  Observer observer(vendor, domain);
  Seen seen;
  const bool discovered = testing::eventually([&] {
    observer.drain();
    seen = look(observer);
    return complete(seen);
  }, retreat::testing::hang_ceiling);
  ASSERT_TRUE(discovered) << "the observer did not see the whole swarm; " << log_of(dir);
  // Let late matches (there must be none) show up, then look again while the swarm runs.
  for (int i = 0; i < 20; ++i) {
    observer.drain();
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_TRUE(l.process.running()) << "the run ended before the check; " << log_of(dir);
  const auto found = violations(look(observer));
  EXPECT_TRUE(found.empty()) << "observer " << vendor << ":" << lines(found);

  // The check sees a breach: a participant calling itself robot 3's agent that reads robot 5's
  // proximity frames and writes robot 7's decisions (it never writes).
  {
    auto rogue = transport::make_transport(vendor, {domain, "rogue", "retreat:agent:robot=3", ""});
    auto reader = rogue->create_reader<wire::ProximityFrame>(
        {wire::proximity_topic("retreat", 5), transport::QosIntent::control()});
    auto writer = rogue->create_writer<wire::Decision>(
        {wire::decision_topic("retreat", 7), transport::QosIntent::control()});
    std::vector<std::string> caught;
    const auto has = [&](const std::string& line) {
      return std::find(caught.begin(), caught.end(), line) != caught.end();
    };
    testing::eventually([&] {
      observer.drain();
      reader.take();
      caught = violations(look(observer));
      return has("retreat:agent:robot=3 reads retreat/robot_5/proximity") &&
             has("retreat:agent:robot=3 writes retreat/robot_7/decision");
    }, retreat::testing::hang_ceiling);
    EXPECT_TRUE(has("retreat:agent:robot=3 reads retreat/robot_5/proximity")) << lines(caught);
    EXPECT_TRUE(has("retreat:agent:robot=3 writes retreat/robot_7/decision")) << lines(caught);
  }

  const auto processes = read_json(l.out + "/processes.json");
  l.process.signal(SIGTERM);
  const auto code = l.process.wait_for(retreat::testing::hang_ceiling);
  ASSERT_TRUE(code.has_value());
  EXPECT_EQ(*code, 128 + SIGTERM) << log_of(dir);
  EXPECT_TRUE(alive(child_pids(processes)).empty());
  // Observing did not disturb the run.
  const auto j = read_json(l.out + "/summary.json");
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["agents"]["lost"], 0);
  EXPECT_EQ(j["agents"]["matched"], 12);
}

INSTANTIATE_TEST_SUITE_P(Observer, LaunchIsolation,
                         ::testing::Values(ObserverCase{"fastdds", testing::domains::launch.at(6)}, ObserverCase{"cyclonedds", testing::domains::launch.at(10)}),
                         [](const auto& test) { return std::string(test.param.vendor); });

}  // namespace
}  // namespace retreat::launch_test
