#include "retreat/scenario/json.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <type_traits>

#include "retreat/core/paths.hpp"
#include "retreat/scenario/archive.hpp"

namespace retreat::scenario {
namespace {

using Json = nlohmann::ordered_json;  // keeps the file's key order, for messages and dumps

std::string value_text(const Json& j) {
  if (j.is_string()) return j.get<std::string>();
  if (j.is_object() || j.is_array()) return "<not a single value>";
  return j.dump();
}

template <class T>
T read_value(const std::string& key, const Json& j) {
  if (j.is_object() || j.is_array()) throw_type_error(key, value_text(j), "a single value");
  if constexpr (std::is_enum_v<T>) {
    if (!j.is_string()) throw_type_error(key, value_text(j), enum_names(T{}).allowed());
    return enum_from_name<T>(key, j.get<std::string>());
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!j.is_boolean()) throw_type_error(key, value_text(j), "true or false");
    return j.get<bool>();
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!j.is_string()) throw_type_error(key, value_text(j), "a string");
    return j.get<std::string>();
  } else if constexpr (std::is_floating_point_v<T>) {
    if (!j.is_number()) throw_type_error(key, value_text(j), "a number");
    return j.get<double>();
  } else {
    static_assert(std::is_integral_v<T>, "a scenario value is a name, bool, string, number or integer");
    const std::string wanted = whole_number_in<T>();
    if (j.is_number_unsigned()) {
      const auto v = j.get<std::uint64_t>();
      if (v > static_cast<std::uint64_t>(std::numeric_limits<T>::max())) throw_type_error(key, value_text(j), wanted);
      return static_cast<T>(v);
    }
    if (j.is_number_integer()) {
      const auto v = j.get<std::int64_t>();
      if (v < static_cast<std::int64_t>(std::numeric_limits<T>::min()) ||
          (v > 0 && static_cast<std::uint64_t>(v) > static_cast<std::uint64_t>(std::numeric_limits<T>::max()))) {
        throw_type_error(key, value_text(j), wanted);
      }
      return static_cast<T>(v);
    }
    // As the YAML loader: a whole number written with a fraction part (8.0) is accepted.
    if (!j.is_number_float()) throw_type_error(key, value_text(j), wanted);
    const auto v = static_cast<long double>(j.get<double>());
    if (v != std::floor(v) || v < static_cast<long double>(std::numeric_limits<T>::min()) ||
        v > static_cast<long double>(std::numeric_limits<T>::max())) {
      throw_type_error(key, value_text(j), wanted);
    }
    return static_cast<T>(v);
  }
}

/// Reads the members present in one JSON object (visiting serialize()).
struct Reader {
  const Json& object;
  std::string prefix;
  const std::string& origin;

  template <class T>
  void operator()(const char* name, T& member) {
    const auto it = object.find(name);
    if (it != object.end()) member = read_value<T>(prefix + name, *it);
  }
  template <class Section>
  void section(const char* name, Section& s) {
    const auto it = object.find(name);
    if (it == object.end() || it->is_null()) return;
    Reader inner{*it, std::string(name) + ".", origin};
    s.serialize(inner);
  }
};

/// Writes every key in serialize() order, a section as a nested object.
struct Writer {
  Json& object;

  template <class T>
  void operator()(const char* name, const T& value) {
    if constexpr (std::is_enum_v<T>) {
      object[name] = std::string(name_of(value));
    } else {
      object[name] = value;
    }
  }
  template <class Section>
  void section(const char* name, Section& s) {
    Json inner = Json::object();
    Writer writer{inner};
    s.serialize(writer);
    object[name] = std::move(inner);
  }
};

/// Refuses, in file order, the first key that serialize() does not name, and a section that is
/// not an object.
void check_keys(const Json& root, const std::string& origin) {
  const auto known = known_keys();
  const auto is_known = [&](const std::string& key) {
    return std::find(known.begin(), known.end(), key) != known.end();
  };
  for (const auto& [name, value] : root.items()) {
    if (is_section(name)) {
      if (value.is_null()) continue;
      if (!value.is_object()) {
        throw ConfigError(name + " in " + origin + ": must be a mapping of keys (" + allowed_in(name) + ")");
      }
      for (const auto& item : value.items()) {
        if (!is_known(name + "." + item.key())) throw_unknown_key(name + "." + item.key(), origin);
      }
    } else if (value.is_object() || !is_known(name)) {
      throw_unknown_key(name, origin);
    }
  }
}

}  // namespace

Scenario parse_json(const std::string& json_text, const std::string& origin) {
  Json root;
  try {
    root = Json::parse(json_text);
  } catch (const Json::parse_error& e) {
    throw ConfigError(origin + ": malformed JSON: " + e.what());
  }
  Scenario s;
  if (!root.is_null()) {
    if (!root.is_object()) throw ConfigError(origin + ": must be a JSON object of sections");
    check_keys(root, origin);
    Reader reader{root, "", origin};
    s.serialize(reader);
  }
  resolve(s);
  validate(s);
  return s;
}

Scenario load_json(const std::string& path) {
  std::ifstream in(path);
  if (!in || retreat::is_directory(path)) {
    throw ConfigError("--scenario '" + path + "': cannot read the file (a JSON scenario)");
  }
  std::stringstream text;
  text << in.rdbuf();
  return parse_json(text.str(), path);
}

std::string dump_json(const Scenario& s) {
  Json root = Json::object();
  Writer writer{root};
  const_cast<Scenario&>(s).serialize(writer);  // serialize() only reads through a Writer
  return root.dump(2) + "\n";
}

}  // namespace retreat::scenario
