#include "retreat/scenario/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "fields.hpp"
#include "retreat/core/paths.hpp"
#include "retreat/model/format_number.hpp"
#include "retreat/wire/topics.hpp"

namespace retreat::scenario {
namespace {

const detail::Field* find_field(const std::string& key) {
  for (const auto& f : detail::fields()) {
    if (f.key == key) return &f;
  }
  return nullptr;
}

std::string allowed_in(const std::string& section) {
  std::string out;
  for (const auto& f : detail::fields()) {
    const auto dot = f.key.find('.');
    const std::string s = dot == std::string::npos ? "" : f.key.substr(0, dot);
    if (s != section) continue;
    out += (out.empty() ? "" : ", ") + (dot == std::string::npos ? f.key : f.key.substr(dot + 1));
  }
  return out;
}

bool is_section(const std::string& name) {
  return std::any_of(detail::fields().begin(), detail::fields().end(),
                     [&](const auto& f) { return f.key.rfind(name + ".", 0) == 0; });
}

[[noreturn]] void unknown_key(const std::string& key, const std::string& origin) {
  const auto dot = key.find('.');
  const std::string section = dot == std::string::npos ? "" : key.substr(0, dot);
  if (!section.empty() && is_section(section)) {
    throw ConfigError("unknown key '" + key + "' in " + origin + " (allowed in " + section +
                      ": " + allowed_in(section) + ")");
  }
  std::string sections = allowed_in("");
  for (const char* s : {"model", "agent", "arena", "run", "dds", "bridge"}) sections += std::string(", ") + s;
  throw ConfigError("unknown key '" + key + "' in " + origin + " (allowed at the top: " +
                    sections + ")");
}

void set_key(Scenario& s, const std::string& key, const YAML::Node& value, const std::string& origin) {
  const auto* f = find_field(key);
  if (f == nullptr) unknown_key(key, origin);
  f->read(s, value);
}

/// A mapping key as text. YAML allows any node as a key (`? [a, b]: 1`); a scenario's keys are
/// names (found by tests/fuzz/scenario_fuzzer.cpp: as<std::string>() threw YAML's own
/// exception, which no program caught).
std::string key_name(const YAML::Node& key, const std::string& origin) {
  if (!key.IsScalar()) {
    throw ConfigError(origin + ": line " + std::to_string(key.Mark().line + 1) +
                      ": a key must be a name (a section or a field), not a list or mapping");
  }
  return key.Scalar();
}

void merge(Scenario& s, const YAML::Node& root, const std::string& origin) {
  if (root.IsNull()) return;  // an empty file: all defaults
  if (!root.IsMap()) throw ConfigError(origin + ": must be a YAML mapping of sections");
  for (const auto& entry : root) {
    const auto name = key_name(entry.first, origin);
    const YAML::Node& value = entry.second;
    if (value.IsMap()) {
      if (!is_section(name)) unknown_key(name, origin);
      for (const auto& item : value) set_key(s, name + "." + key_name(item.first, origin), item.second, origin);
    } else if (is_section(name) && !value.IsNull()) {
      throw ConfigError(name + " in " + origin + ": must be a mapping of keys (" + allowed_in(name) + ")");
    } else if (!is_section(name)) {
      set_key(s, name, value, origin);
    }
  }
}

void check(bool ok, const std::string& key, const std::string& value, const std::string& allowed) {
  if (!ok) throw ConfigError(key + " = " + value + ": " + allowed);
}

std::string num(double v) { return model::format_number(v); }

void validate_run(const RunParams& r) {
  check(r.mode == "lockstep" || r.mode == "realtime", "run.mode", "'" + r.mode + "'",
        "must be one of lockstep, realtime");
  check(std::isfinite(r.speed) && r.speed > 0, "run.speed", num(r.speed), "must be > 0 (simulated s per wall s)");
  check(std::isfinite(r.duration) && r.duration > 0, "run.duration", num(r.duration), "must be > 0 (s)");
  check(std::isfinite(r.agent_timeout) && r.agent_timeout > 0, "run.agent_timeout",
        num(r.agent_timeout), "must be > 0 (wall s)");
  check(std::isfinite(r.startup_timeout) && r.startup_timeout > 0, "run.startup_timeout",
        num(r.startup_timeout), "must be > 0 (wall s)");
  check(std::isfinite(r.status_period) && r.status_period > 0, "run.status_period",
        num(r.status_period), "must be > 0 (s)");
  check(std::isfinite(r.telemetry_period) && r.telemetry_period > 0, "run.telemetry_period",
        num(r.telemetry_period), "must be > 0 (s)");
}

void validate_dds(const DdsParams& d) {
  check(d.vendor == "fastdds" || d.vendor == "cyclonedds" || d.vendor == "inmemory", "dds.vendor",
        "'" + d.vendor + "'", "must be one of fastdds, cyclonedds, inmemory");
  check(d.domain >= 0 && d.domain <= 232, "dds.domain", std::to_string(d.domain),
        "must be an integer in 0..232");
  check(wire::is_valid_prefix(d.prefix), "dds.prefix", "'" + d.prefix + "'",
        "must be 1..64 characters of letters, digits and _, with single / between parts");
  check(d.profile.empty() || retreat::is_regular_file(d.profile), "dds.profile",
        "'" + d.profile + "'", "no such file (a vendor XML profile; empty for built-in loopback)");
  check(d.security == "on" || d.security == "off", "dds.security", "'" + d.security + "'",
        "must be on or off");
  check(d.security == "off" || retreat::is_regular_file(d.security_dir + "/ca.pem"),
        "dds.security_dir", "'" + d.security_dir + "'",
        "must be a directory made by deploy/security/make-swarm-pki.sh (with ca.pem) when "
        "dds.security is on");
  check(d.security == "off" || d.vendor != "inmemory", "dds.security", "'on'",
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

void apply_override(Scenario& s, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ConfigError("--set '" + assignment + "': must be section.key=value");
  }
  const std::string key = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception&) {
    value = YAML::Node(assignment.substr(eq + 1));
  }
  if (value.IsNull()) value = YAML::Node(std::string());
  set_key(s, key, value, "--set");
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
}

void validate(const Scenario& s) {
  as_config_error([&] { s.model.validate(); });
  as_config_error([&] { s.agent.validate(); });
  as_config_error([&] { s.arena.validate(); });
  validate_run(s.run);
  validate_dds(s.dds);
  validate_bridge(s.bridge);
}

Scenario parse(const std::string& yaml_text, const std::vector<std::string>& overrides,
               const std::string& origin) {
  Scenario s;
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(origin + ": malformed YAML at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  merge(s, root, origin);
  for (const auto& o : overrides) apply_override(s, o);
  resolve(s);
  validate(s);
  return s;
}

Scenario load(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in || retreat::is_directory(path)) {
    throw ConfigError("--scenario '" + path + "': cannot read the file (a YAML scenario)");
  }
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), overrides, path);
}

std::string dump(const Scenario& s) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  std::string open_section;
  for (const auto& f : detail::fields()) {
    const auto dot = f.key.find('.');
    const std::string section = dot == std::string::npos ? "" : f.key.substr(0, dot);
    if (section != open_section) {
      if (!open_section.empty()) out << YAML::EndMap;
      if (!section.empty()) out << YAML::Key << section << YAML::Value << YAML::BeginMap;
      open_section = section;
    }
    f.write(s, out);
  }
  if (!open_section.empty()) out << YAML::EndMap;
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::vector<std::string> known_keys() {
  std::vector<std::string> out;
  for (const auto& f : detail::fields()) out.push_back(f.key);
  return out;
}

bool has_robot(const Scenario& s, std::uint64_t robot_id) {
  if (s.arena.queue == "endless") return robot_id <= 0xFFFFFFFFull;
  return robot_id < static_cast<std::uint64_t>(s.arena.robots_inside) + s.arena.robots_waiting;
}

}  // namespace retreat::scenario
