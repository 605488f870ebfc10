#include "fields.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "retreat/model/format_number.hpp"

namespace retreat::scenario::detail {
namespace {

std::string scalar_text(const YAML::Node& node) {
  return node.IsScalar() ? node.Scalar() : std::string("<not a single value>");
}

[[noreturn]] void type_error(const std::string& key, const YAML::Node& node, const char* wanted) {
  throw ConfigError(key + " = '" + scalar_text(node) + "': must be " + wanted);
}

template <class T>
T read_value(const std::string& key, const YAML::Node& node) {
  if (!node.IsScalar()) type_error(key, node, "a single value");
  if constexpr (std::is_same_v<T, bool>) {
    bool value = false;
    if (!YAML::convert<bool>::decode(node, value)) type_error(key, node, "true or false");
    return value;
  } else if constexpr (std::is_same_v<T, std::string>) {
    return node.Scalar();
  } else if constexpr (std::is_floating_point_v<T>) {
    double value = 0.0;
    if (!YAML::convert<double>::decode(node, value) || std::isnan(value)) {
      type_error(key, node, "a number");
    }
    return value;
  } else {
    // Integers: parse as long double to catch fractions and out-of-range values cleanly.
    long double value = 0.0L;
    std::istringstream in(node.Scalar());
    in >> value;
    if (!in || !in.eof() || value != std::floor(value) ||
        value < static_cast<long double>(std::numeric_limits<T>::min()) ||
        value > static_cast<long double>(std::numeric_limits<T>::max())) {
      if constexpr (std::is_signed_v<T>) {
        type_error(key, node, "a whole number");
      } else {
        type_error(key, node, "a whole number >= 0");
      }
    }
    return static_cast<T>(value);
  }
}

template <class T>
void write_value(YAML::Emitter& out, const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    out << YAML::Value << model::format_number(value);  // shortest text that reads back exactly
  } else {
    out << YAML::Value << value;
  }
}

/// A field for a member of a section: `section.member`.
template <class Section, class T>
Field field(const char* section_name, const char* name, Section Scenario::*section,
            T Section::*member) {
  const std::string key = std::string(section_name) + "." + name;
  return Field{key,
               [=](Scenario& s, const YAML::Node& node) {
                 (s.*section).*member = read_value<T>(key, node);
               },
               [=](const Scenario& s, YAML::Emitter& out) {
                 out << YAML::Key << name;
                 write_value(out, (s.*section).*member);
               }};
}

/// A top-level field: `key`.
template <class T>
Field top(const char* name, T Scenario::*member) {
  return Field{name,
               [=](Scenario& s, const YAML::Node& node) { s.*member = read_value<T>(name, node); },
               [=](const Scenario& s, YAML::Emitter& out) {
                 out << YAML::Key << name;
                 write_value(out, s.*member);
               }};
}

std::vector<Field> make_fields() {
  using model::ModelParams;
  using agent::AgentParams;
  using physics::WorldParams;
  const auto m = &Scenario::model;
  const auto a = &Scenario::agent;
  const auto w = &Scenario::arena;
  const auto r = &Scenario::run;
  const auto d = &Scenario::dds;
  const auto b = &Scenario::bridge;
  return {
      top("name", &Scenario::name),
      top("seed", &Scenario::seed),
      field("model", "lambda_p", m, &ModelParams::lambda_p),
      field("model", "lambda_d", m, &ModelParams::lambda_d),
      field("model", "C", m, &ModelParams::C),
      field("model", "delta", m, &ModelParams::delta),
      field("model", "v", m, &ModelParams::v),
      field("model", "rho", m, &ModelParams::rho),
      field("agent", "L", a, &AgentParams::L),
      field("agent", "dt", a, &AgentParams::dt),
      field("agent", "K_p", a, &AgentParams::K_p),
      field("agent", "lambda_in", a, &AgentParams::lambda_in),
      field("agent", "controller", a, &AgentParams::controller),
      field("arena", "encounter_model", w, &WorldParams::encounter_model),
      field("arena", "shape", w, &WorldParams::shape),
      field("arena", "semi_axis_x", w, &WorldParams::semi_axis_x),
      field("arena", "semi_axis_y", w, &WorldParams::semi_axis_y),
      field("arena", "width", w, &WorldParams::width),
      field("arena", "height", w, &WorldParams::height),
      field("arena", "robots_inside", w, &WorldParams::robots_inside),
      field("arena", "robots_waiting", w, &WorldParams::robots_waiting),
      field("arena", "queue", w, &WorldParams::queue),
      field("arena", "influx", w, &WorldParams::influx),
      field("arena", "physics_dt", w, &WorldParams::physics_dt),
      field("arena", "robot_radius", w, &WorldParams::robot_radius),
      field("arena", "max_speed", w, &WorldParams::max_speed),
      field("arena", "max_turn_rate", w, &WorldParams::max_turn_rate),
      field("arena", "gamma", w, &WorldParams::gamma),
      field("arena", "safety_distance", w, &WorldParams::safety_distance),
      field("arena", "projection_distance", w, &WorldParams::projection_distance),
      field("arena", "boundary_gain", w, &WorldParams::boundary_gain),
      field("arena", "tumble_rate", w, &WorldParams::tumble_rate),
      field("arena", "unblock_time", w, &WorldParams::unblock_time),
      field("arena", "record_encounters", w, &WorldParams::record_encounters),
      field("run", "mode", r, &RunParams::mode),
      field("run", "speed", r, &RunParams::speed),
      field("run", "duration", r, &RunParams::duration),
      field("run", "agent_timeout", r, &RunParams::agent_timeout),
      field("run", "startup_timeout", r, &RunParams::startup_timeout),
      field("run", "status_period", r, &RunParams::status_period),
      field("run", "telemetry_period", r, &RunParams::telemetry_period),
      field("dds", "vendor", d, &DdsParams::vendor),
      field("dds", "domain", d, &DdsParams::domain),
      field("dds", "prefix", d, &DdsParams::prefix),
      field("dds", "profile", d, &DdsParams::profile),
      field("dds", "security", d, &DdsParams::security),
      field("dds", "security_dir", d, &DdsParams::security_dir),
      field("bridge", "http", b, &BridgeParams::http),
  };
}

}  // namespace

const std::vector<Field>& fields() {
  static const std::vector<Field> table = make_fields();
  return table;
}

}  // namespace retreat::scenario::detail
