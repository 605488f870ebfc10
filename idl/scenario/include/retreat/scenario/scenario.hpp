#pragma once
/// @file
/// One scenario file (YAML) describes a run. This is its in-memory form: plain structs with
/// defaults, one per section, owned by the libraries that use them. Every program reads the
/// sections it needs; every program validates the whole scenario at start-up.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/agent/agent_params.hpp"
#include "retreat/model/params.hpp"
#include "retreat/physics/params.hpp"

namespace retreat::scenario {

/// Bad scenario input: the message is one line naming the key, the value and what is allowed.
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// `run.*`: how time advances and when the run ends.
struct RunParams {
  std::string mode = "lockstep";  ///< `lockstep` or `realtime`
  double speed = 1.0;             ///< real-time acceleration (simulated s per wall s), > 0
  double duration = 1200.0;       ///< simulated run length [s], > 0
  double agent_timeout = 5.0;     ///< lockstep: an agent silent this long is lost [wall s], > 0
  double startup_timeout = 60.0;  ///< lockstep: how long the arena waits for agents to match [wall s]
  double status_period = 1.0;     ///< agents publish their status this often [simulated s], > 0
  double telemetry_period = 0.1;  ///< the arena publishes telemetry and poses this often [simulated s]
};

/// `dds.*`: the middleware.
struct DdsParams {
  std::string vendor = "fastdds";  ///< `fastdds`, `cyclonedds` (or `inmemory` in-process)
  int domain = 0;                  ///< DDS domain id, 0..232
  std::string prefix = "retreat";  ///< topic prefix
  std::string profile;             ///< vendor XML profile; empty = built-in loopback settings
  std::string security = "off";    ///< DDS Security: `on` or `off` (docs/security.md)
  std::string security_dir;        ///< the swarm's PKI (deploy/security/make-swarm-pki.sh); needed when on
};

/// `bridge.*`: the telemetry bridge.
struct BridgeParams {
  std::string http = "127.0.0.1:8080";  ///< HOST:PORT to serve on; port 0 picks a free port
};

struct Scenario {
  std::string name = "unnamed";  ///< `name`
  std::uint64_t seed = 1;        ///< `seed`: every random stream derives from it
  model::ModelParams model;
  agent::AgentParams agent;
  physics::WorldParams arena;  ///< `arena.*`; its copies of model/agent values are filled in
  RunParams run;
  DdsParams dds;
  BridgeParams bridge;
};

/// Loads a scenario: defaults, then the file, then each `section.key=value` override in order;
/// then fills the arena's copies of shared values and validates everything.
/// Throws ConfigError (missing or malformed file, unknown key, wrong type, out of range).
Scenario load(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same as load() from YAML text (for tests and in-process runs).
Scenario parse(const std::string& yaml_text, const std::vector<std::string>& overrides = {},
               const std::string& origin = "<text>");

/// Applies one `section.key=value` override (YAML scalar syntax for the value).
void apply_override(Scenario& scenario, const std::string& assignment);

/// Copies shared values into the sections that need them (arena.tick_dt = agent.dt, ...).
void resolve(Scenario& scenario);

/// Validates every section and the cross-section rules; throws ConfigError.
void validate(const Scenario& scenario);

/// The resolved scenario as YAML: loading it again gives the same Scenario.
std::string dump(const Scenario& scenario);

/// Every key a scenario file may contain (`section.key` or top-level `key`).
std::vector<std::string> known_keys();

/// Robot ids an agent may serve: 0 .. robots_inside + robots_waiting − 1 for a finite queue;
/// any id for an endless queue.
bool has_robot(const Scenario& scenario, std::uint64_t robot_id);

}  // namespace retreat::scenario
