#include "retreat/scenario/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <type_traits>

#include "retreat/core/paths.hpp"
#include "retreat/model/format_number.hpp"
#include "retreat/scenario/archive.hpp"

namespace retreat::scenario {
namespace {

std::string scalar_text(const YAML::Node& node) {
  return node.IsScalar() ? node.Scalar() : std::string("<not a single value>");
}

template <class T>
T read_value(const std::string& key, const YAML::Node& node) {
  if (!node.IsScalar()) throw_type_error(key, scalar_text(node), "a single value");
  if constexpr (std::is_enum_v<T>) {
    return enum_from_name<T>(key, node.Scalar());
  } else if constexpr (std::is_same_v<T, bool>) {
    bool value = false;
    if (!YAML::convert<bool>::decode(node, value)) throw_type_error(key, node.Scalar(), "true or false");
    return value;
  } else if constexpr (std::is_same_v<T, std::string>) {
    return node.Scalar();
  } else if constexpr (std::is_floating_point_v<T>) {
    double value = 0.0;
    if (!YAML::convert<double>::decode(node, value) || std::isnan(value)) {
      throw_type_error(key, node.Scalar(), "a number");
    }
    return value;
  } else {
    static_assert(std::is_integral_v<T>, "a scenario value is a name, bool, string, number or integer");
    // Integers: parse as long double to catch fractions and out-of-range values cleanly.
    long double value = 0.0L;
    std::istringstream in(node.Scalar());
    in >> value;
    if (!in || !in.eof() || value != std::floor(value) ||
        value < static_cast<long double>(std::numeric_limits<T>::min()) ||
        value > static_cast<long double>(std::numeric_limits<T>::max())) {
      throw_type_error(key, node.Scalar(), whole_number_in<T>());
    }
    return static_cast<T>(value);
  }
}

/// Sets the one member whose key is `key` (visiting Scenario::serialize()); `found` tells
/// whether there was one.
struct SetOne {
  const std::string& key;
  const YAML::Node& value;
  std::string prefix;
  bool found = false;

  template <class T>
  void operator()(const char* name, T& member) {
    if (found || prefix + name != key) return;
    member = read_value<T>(key, value);
    found = true;
  }
  template <class Section>
  void section(const char* name, Section& s) {
    if (found || key.rfind(std::string(name) + ".", 0) != 0) return;
    SetOne inner{key, value, std::string(name) + "."};
    s.serialize(inner);
    found = inner.found;
  }
};

/// Writes every key in serialize() order, a section as a nested mapping.
struct Writer {
  YAML::Emitter& out;

  template <class T>
  void operator()(const char* name, const T& value) {
    out << YAML::Key << name << YAML::Value;
    if constexpr (std::is_enum_v<T>) {
      out << std::string(name_of(value));
    } else if constexpr (std::is_floating_point_v<T>) {
      out << model::format_number(value);  // shortest text that reads back exactly
    } else {
      out << value;
    }
  }
  template <class Section>
  void section(const char* name, Section& s) {
    out << YAML::Key << name << YAML::Value << YAML::BeginMap;
    s.serialize(*this);
    out << YAML::EndMap;
  }
};

void set_key(Scenario& s, const std::string& key, const YAML::Node& value, const std::string& origin) {
  SetOne setter{key, value, ""};
  s.serialize(setter);
  if (!setter.found) throw_unknown_key(key, origin);
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
  // YAML forbids a key twice in one mapping, but yaml-cpp keeps both and the later one would
  // silently win: a scenario with two values for one key is refused, naming the second.
  std::set<std::string> seen;
  const auto first_time = [&](const std::string& key, const YAML::Node& node) {
    if (!seen.insert(key).second) {
      throw ConfigError(key + " in " + origin + ": given twice (again at line " + std::to_string(node.Mark().line + 1) +
                        "); a scenario gives each key once");
    }
  };
  for (const auto& entry : root) {
    const auto name = key_name(entry.first, origin);
    first_time(name, entry.first);
    const YAML::Node& value = entry.second;
    if (value.IsMap()) {
      if (!is_section(name)) throw_unknown_key(name, origin);
      for (const auto& item : value) {
        const auto key = name + "." + key_name(item.first, origin);
        first_time(key, item.first);
        set_key(s, key, item.second, origin);
      }
    } else if (is_section(name) && !value.IsNull()) {
      throw ConfigError(name + " in " + origin + ": must be a mapping of keys (" + allowed_in(name) + ")");
    } else if (!is_section(name)) {
      set_key(s, name, value, origin);
    }
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
  Writer writer{out};
  const_cast<Scenario&>(s).serialize(writer);  // serialize() only reads through a Writer
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace retreat::scenario
