#pragma once
/// @file
/// A scenario in memory: plain structs with defaults, one per section, each declaring its own
/// keys beside itself (`serialize()`, the Drake `Serialize()` idiom), owned by the libraries that
/// use them. Standard library only: a file format is a separate layer that visits `serialize()`
/// (retreat/scenario/scenario.hpp reads and writes YAML, retreat/scenario/json.hpp JSON).

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/agent/agent_params.hpp"
#include "retreat/agent/retreat_agent.hpp"
#include "retreat/core/enum_names.hpp"
#include "retreat/model/params.hpp"
#include "retreat/physics/params.hpp"

namespace retreat::scenario {

/// Bad scenario input: the message is one line naming the key, the value and what is allowed.
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// How simulated time advances (`run.mode`).
enum class RunMode {
  lockstep,  ///< the arena waits for every agent's decision before the next tick
  realtime,  ///< ticks follow the wall clock (times run.speed); late decisions are missed
};
constexpr EnumNames<RunMode, 2> enum_names(RunMode) {
  return {{{{RunMode::lockstep, "lockstep"}, {RunMode::realtime, "realtime"}}}};
}

/// The middleware of a run (`dds.vendor`). The transport factory takes its name (name_of).
enum class Vendor {
  fastdds,     ///< eProsima Fast DDS
  cyclonedds,  ///< Eclipse Cyclone DDS
  inmemory,    ///< no DDS: one process, the in-memory transport
};
constexpr EnumNames<Vendor, 3> enum_names(Vendor) {
  return {{{{Vendor::fastdds, "fastdds"}, {Vendor::cyclonedds, "cyclonedds"},
            {Vendor::inmemory, "inmemory"}}}};
}

/// DDS Security (`dds.security`), spelled `on` / `off` in scenario files.
enum class Security { off, on };
constexpr EnumNames<Security, 2> enum_names(Security) {
  return {{{{Security::off, "off"}, {Security::on, "on"}}}, "on or off"};
}

/// `run.*`: how time advances and when the run ends.
struct RunParams {
  RunMode mode = RunMode::lockstep;  ///< `lockstep` or `realtime`
  double speed = 1.0;             ///< real-time acceleration (simulated s per wall s), > 0
  double duration = 1200.0;       ///< simulated run length [s], > 0
  /// Lockstep: an agent silent this long whose answer writer the arena no longer matches (its
  /// process ended, or its participant's lease expired) is lost [wall s], > 0.
  double agent_timeout = 5.0;
  /// Lockstep: an agent silent this long is lost even though its answer writer is still matched
  /// (a hung process whose DDS threads keep it alive) [wall s], >= agent_timeout. A slow, loaded
  /// machine is not a dead agent: until then the arena waits for an agent that is still there.
  double agent_hang_timeout = 120.0;
  double startup_timeout = 60.0;  ///< lockstep: how long the arena waits for agents to match [wall s]
  double status_period = 1.0;     ///< agents publish their status this often [simulated s], > 0
  double telemetry_period = 0.1;  ///< the arena publishes telemetry and poses this often [simulated s]
  /// Lockstep only: agents answer a frame with a plan, their decisions for the coming ticks while
  /// their robot's input stays unchanged, and the arena sends a robot a frame only when its input
  /// changes or its plan ends (event-driven lockstep; docs/protocol.md §6). Same trajectory.
  bool plans = false;
  std::uint32_t plan_horizon = 500;  ///< ticks a plan covers at most, 1..1,000,000
  /// Recorders (retreat-record) the arena and every agent wait for, up to run.startup_timeout,
  /// before their robot's traffic begins, so that a recording holds every sample; 0..8.
  /// `retreat-launch --record` sets it to 1. The trajectory does not depend on it.
  std::uint32_t recorders = 0;

  template <class Archive>
  void serialize(Archive& a) {
    a("mode", mode);
    a("speed", speed);
    a("duration", duration);
    a("agent_timeout", agent_timeout);
    a("agent_hang_timeout", agent_hang_timeout);
    a("startup_timeout", startup_timeout);
    a("status_period", status_period);
    a("telemetry_period", telemetry_period);
    a("plans", plans);
    a("plan_horizon", plan_horizon);
    a("recorders", recorders);
  }
};

/// `dds.*`: the middleware.
struct DdsParams {
  Vendor vendor = Vendor::fastdds;     ///< `fastdds`, `cyclonedds` (or `inmemory` in-process)
  int domain = 0;                      ///< DDS domain id, 0..232
  /// Domains the swarm spans, domain .. domain + domains - 1 (1..64): robot r's topics on
  /// domain + r mod domains; the arena, bridge and recorder join every one. Discovery is per
  /// domain, so K domains divide a hub's discovery work by K (docs/dds-profiles.md).
  int domains = 1;
  std::string prefix = "retreat";      ///< topic prefix
  std::string profile;                 ///< vendor XML profile; empty = built-in loopback settings
  Security security = Security::off;   ///< DDS Security: `on` or `off` (docs/security.md)
  std::string security_dir;  ///< the swarm's PKI (deploy/security/make-swarm-pki.sh); needed when on

  template <class Archive>
  void serialize(Archive& a) {
    a("vendor", vendor);
    a("domain", domain);
    a("domains", domains);
    a("prefix", prefix);
    a("profile", profile);
    a("security", security);
    a("security_dir", security_dir);
  }
};

/// `bridge.*`: the telemetry bridge.
struct BridgeParams {
  std::string http = "127.0.0.1:8080";  ///< HOST:PORT to serve on; port 0 picks a free port

  template <class Archive>
  void serialize(Archive& a) {
    a("http", http);
  }
};

/// One run: the top-level `name` and `seed`, then one section per library.
struct Scenario {
  std::string name = "unnamed";  ///< `name`
  std::uint64_t seed = 1;        ///< `seed`: every random stream derives from it
  model::ModelParams model;
  agent::AgentParams agent;
  physics::WorldParams arena;  ///< `arena.*`; its copies of model/agent values are filled in
  RunParams run;
  DdsParams dds;
  BridgeParams bridge;

  /// Visits every key in file order: `a(name, member)` for a top-level key,
  /// `a.section(name, section)` for a section (whose own serialize() names its keys).
  template <class Archive>
  void serialize(Archive& a) {
    a("name", name);
    a("seed", seed);
    a.section("model", model);
    a.section("agent", agent);
    a.section("arena", arena);
    a.section("run", run);
    a.section("dds", dds);
    a.section("bridge", bridge);
  }
};

/// Copies shared values into the sections that need them (arena.tick_dt = agent.dt, ...).
void resolve(Scenario& scenario);

/// Expected arrivals over a run with an endless queue, agent.lambda_in·|D|·run.duration, at most:
/// each one that enters is a robot (with its agent) for the rest of the run. A run of
/// steady-influx.yaml has about 217. (A finite queue's arrivals beyond its robots are dropped;
/// physics::max_arrivals_per_tick bounds the draws of either.)
inline constexpr double max_arrivals_per_run = 1e7;

/// Validates every section and the cross-section rules (among them max_arrivals_per_run);
/// throws ConfigError.
void validate(const Scenario& scenario);

/// Every key a scenario file may contain (`section.key` or top-level `key`), in file order.
std::vector<std::string> known_keys();

/// Robot ids an agent may serve: 0 .. robots_inside + robots_waiting − 1 for a finite queue;
/// any id for an endless queue.
bool has_robot(const Scenario& scenario, std::uint64_t robot_id);

/// When the arena's frames are: frame `tick` at static_cast<double>(tick · multiplier) · period,
/// computed as the world computes it (kinetic: 1 × agent.dt; physical: the physics steps per tick
/// × arena.physics_dt), so that an agent planning ahead knows its coming frames' times exactly.
agent::FrameClock frame_clock(const Scenario& scenario);

}  // namespace retreat::scenario
