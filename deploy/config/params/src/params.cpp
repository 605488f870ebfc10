#include "retreat/scenario/params.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "retreat/core/paths.hpp"
#include "retreat/model/format_number.hpp"
#include "retreat/scenario/archive.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::scenario {
namespace {

/// Collects the keys Scenario::serialize() visits: `section.key`, or `key` at the top.
struct KeyLister {
  std::vector<std::string>& keys;
  std::vector<std::string>& sections;
  std::string prefix;

  template <class T>
  void operator()(const char* name, T& /*member*/) {
    keys.push_back(prefix + name);
  }
  template <class Section>
  void section(const char* name, Section& s) {
    sections.emplace_back(name);
    KeyLister inner{keys, sections, std::string(name) + "."};
    s.serialize(inner);
  }
};

struct KeyIndex {
  std::vector<std::string> keys;
  std::vector<std::string> sections;
};

const KeyIndex& key_index() {
  static const KeyIndex index = [] {
    KeyIndex out;
    Scenario defaults;
    KeyLister lister{out.keys, out.sections, ""};
    defaults.serialize(lister);
    return out;
  }();
  return index;
}

void check(bool ok, const std::string& key, const std::string& value, const std::string& allowed) {
  if (!ok) throw ConfigError(key + " = " + value + ": " + allowed);
}

std::string num(double v) { return model::format_number(v); }

void validate_run(const RunParams& r) {
  check(value_of<RunMode>(name_of(r.mode)).has_value(), "run.mode",
        std::to_string(static_cast<int>(r.mode)), "must be " + enum_names(r.mode).allowed());
  check(std::isfinite(r.speed) && r.speed > 0, "run.speed", num(r.speed), "must be > 0 (simulated s per wall s)");
  check(std::isfinite(r.duration) && r.duration > 0, "run.duration", num(r.duration), "must be > 0 (s)");
  check(std::isfinite(r.agent_timeout) && r.agent_timeout > 0, "run.agent_timeout",
        num(r.agent_timeout), "must be > 0 (wall s)");
  check(std::isfinite(r.agent_hang_timeout) && r.agent_hang_timeout >= r.agent_timeout, "run.agent_hang_timeout",
        num(r.agent_hang_timeout), "must be >= run.agent_timeout (" + num(r.agent_timeout) + " wall s)");
  check(std::isfinite(r.startup_timeout) && r.startup_timeout > 0, "run.startup_timeout",
        num(r.startup_timeout), "must be > 0 (wall s)");
  check(std::isfinite(r.status_period) && r.status_period > 0, "run.status_period",
        num(r.status_period), "must be > 0 (s)");
  check(std::isfinite(r.telemetry_period) && r.telemetry_period > 0, "run.telemetry_period",
        num(r.telemetry_period), "must be > 0 (s)");
  check(r.plan_horizon >= 1 && r.plan_horizon <= 1000000, "run.plan_horizon", std::to_string(r.plan_horizon),
        "must be in 1..1000000 (ticks)");
  check(r.recorders <= 8, "run.recorders", std::to_string(r.recorders),
        "must be in 0..8 (recorders to wait for)");
}

void validate_dds(const DdsParams& d) {
  // Enum members hold named values unless cast: these two checks guard against casts only.
  check(value_of<Vendor>(name_of(d.vendor)).has_value(), "dds.vendor",
        std::to_string(static_cast<int>(d.vendor)), "must be " + enum_names(d.vendor).allowed());
  check(value_of<Security>(name_of(d.security)).has_value(), "dds.security",
        std::to_string(static_cast<int>(d.security)), "must be " + enum_names(d.security).allowed());
  const auto last_id = std::to_string(wire::max_domain_id);
  check(d.domain >= 0 && d.domain <= wire::max_domain_id, "dds.domain", std::to_string(d.domain),
        "must be an integer in 0.." + last_id);
  const int most = wire::max_domains_from(d.domain);
  check(d.domains >= 1 && d.domains <= most, "dds.domains", std::to_string(d.domains),
        "must be an integer in 1.." + std::to_string(most) + " (dds.domain " + std::to_string(d.domain) +
            " + dds.domains - 1 must be a domain id, at most " + last_id + ")");
  check(wire::is_valid_prefix(d.prefix), "dds.prefix", "'" + d.prefix + "'",
        "must be 1..64 characters of letters, digits and _, with single / between parts");
  check(d.profile.empty() || retreat::is_regular_file(d.profile), "dds.profile",
        "'" + d.profile + "'",
        "must be an existing file (a vendor XML profile; empty for built-in loopback)");
  const bool secure = d.security == Security::on;
  check(!secure || retreat::is_regular_file(d.security_dir + "/ca.pem"), "dds.security_dir",
        "'" + d.security_dir + "'",
        "must be a directory made by deploy/security/make-swarm-pki.sh (with ca.pem) when "
        "dds.security is on");
  check(!secure || d.vendor != Vendor::inmemory, "dds.security", "'on'",
        "needs a DDS vendor (fastdds or cyclonedds): the in-memory transport has no DDS Security");
}

void validate_bridge(const BridgeParams& b) {
  const auto colon = b.http.rfind(':');
  bool ok = colon != std::string::npos && colon > 0;
  if (ok) {
    unsigned port = 0;
    const char* first = b.http.data() + colon + 1;
    const char* last = b.http.data() + b.http.size();
    const auto [end, error] = std::from_chars(first, last, port);
    ok = error == std::errc() && end == last && first != last && port <= 65535;
  }
  check(ok, "bridge.http", "'" + b.http + "'", "must be HOST:PORT with PORT in 0..65535");
}

/// Rethrows any std::invalid_argument from a library's validate() as a ConfigError.
template <class F>
void as_config_error(F&& f) {
  try {
    f();
  } catch (const ConfigError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw ConfigError(e.what());
  }
}

}  // namespace

bool is_section(std::string_view name) {
  const auto& sections = key_index().sections;
  return std::find(sections.begin(), sections.end(), name) != sections.end();
}

std::string allowed_in(std::string_view section) {
  std::string out;
  for (const auto& key : key_index().keys) {
    const auto dot = key.find('.');
    const std::string_view s = dot == std::string::npos ? std::string_view() : std::string_view(key).substr(0, dot);
    if (s != section) continue;
    out += (out.empty() ? "" : ", ") + (dot == std::string::npos ? key : key.substr(dot + 1));
  }
  if (section.empty()) {
    for (const auto& s : key_index().sections) out += (out.empty() ? "" : ", ") + s;
  }
  return out;
}

void throw_unknown_key(const std::string& key, const std::string& origin) {
  const auto dot = key.find('.');
  const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
  if (!section.empty() && is_section(section)) {
    throw ConfigError("unknown key '" + key + "' in " + origin + " (allowed in " + section +
                      ": " + allowed_in(section) + ")");
  }
  throw ConfigError("unknown key '" + key + "' in " + origin + " (allowed at the top: " +
                    allowed_in("") + ")");
}

void throw_type_error(const std::string& key, const std::string& text, const std::string& wanted) {
  throw ConfigError(key + " = '" + text + "': must be " + wanted);
}

void resolve(Scenario& s) {
  s.arena.tick_dt = s.agent.dt;
  s.arena.lambda_in = s.agent.lambda_in;
  s.arena.seed = s.seed;
  s.arena.v = s.model.v;
  s.arena.delta = s.model.delta;
  s.arena.lambda_p = s.model.lambda_p;
  s.arena.lambda_d = s.model.lambda_d;
  s.arena.rho = s.model.rho;
  // Plans are lockstep's (the shipped scenarios set them): in real time every frame is sent when
  // it happens, so there they are off, and the resolved scenario says so.
  if (s.run.mode == RunMode::realtime) s.run.plans = false;
}

void validate(const Scenario& s) {
  as_config_error([&] { s.model.validate(); });
  as_config_error([&] { s.agent.validate(); });
  as_config_error([&] { s.arena.validate(); });
  validate_run(s.run);
  const double area = physics::domain_of(s.arena).area();
  const double arrivals = s.agent.lambda_in * area * s.run.duration;
  check(s.arena.queue == physics::QueueKind::finite || arrivals <= max_arrivals_per_run, "agent.lambda_in",
        num(s.agent.lambda_in),
        "must be <= " + num(max_arrivals_per_run / (area * s.run.duration)) +
            " robots/(m^2 s) with this arena (|D| = " + num(area) + " m^2), run.duration = " + num(s.run.duration) +
            " s and arena.queue = endless: " + num(arrivals) + " robots would join, at most " +
            num(max_arrivals_per_run));
  validate_dds(s.dds);
  validate_bridge(s.bridge);
  check(s.arena.external_robots == 0 || (s.run.mode == RunMode::realtime && s.dds.vendor != Vendor::inmemory),
        "arena.external_robots", std::to_string(s.arena.external_robots),
        "must be 0 unless run.mode is realtime over DDS (a real robot keeps its own clock and "
        "publishes its pose over DDS)");
}

std::vector<std::string> known_keys() { return key_index().keys; }

bool has_robot(const Scenario& s, std::uint64_t robot_id) {
  if (s.arena.queue == physics::QueueKind::endless) return robot_id <= 0xFFFFFFFFull;
  return robot_id < static_cast<std::uint64_t>(s.arena.robots_inside) + s.arena.robots_waiting;
}

agent::FrameClock frame_clock(const Scenario& s) {
  if (s.arena.encounter_model == physics::EncounterModel::kinetic) return {1, s.arena.tick_dt};
  return {physics::substeps_per_tick(s.arena), s.arena.physics_dt};
}

}  // namespace retreat::scenario
