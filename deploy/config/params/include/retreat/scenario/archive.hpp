#pragma once
/// @file
/// What every scenario file format shares (the YAML loader, the JSON reader and writer): the
/// keys as Scenario::serialize() names them, and the one-line messages for an unknown key, a
/// value of the wrong type and a name outside an enum's table. Standard library only.

#include <limits>
#include <string>
#include <string_view>

#include "retreat/core/enum_names.hpp"
#include "retreat/scenario/params.hpp"

namespace retreat::scenario {

/// Whether @p name is a section (`model`, `agent`, ...) rather than a top-level key.
bool is_section(std::string_view name);

/// The keys allowed in @p section, comma-separated (`L, dt, K_p, ...`); for "" the top-level
/// keys followed by the section names.
std::string allowed_in(std::string_view section);

/// `unknown key 'agent.window' in <origin> (allowed in agent: L, dt, ...)`, or for a key in no
/// section `(allowed at the top: name, seed, model, ...)`.
[[noreturn]] void throw_unknown_key(const std::string& key, const std::string& origin);

/// `<key> = '<text>': must be <wanted>`.
[[noreturn]] void throw_type_error(const std::string& key, const std::string& text,
                                   const std::string& wanted);

/// `a whole number in MIN..MAX` for the integer type @p T: what an integer key allows.
template <class T>
std::string whole_number_in() {
  return "a whole number in " + std::to_string(std::numeric_limits<T>::min()) + ".." +
         std::to_string(std::numeric_limits<T>::max());
}

/// The value of @p E named @p text, or a ConfigError such as
/// `arena.shape = 'circle': must be one of ellipse, rectangle`.
template <NamedEnum E>
E enum_from_name(const std::string& key, const std::string& text) {
  if (const auto value = value_of<E>(text)) return *value;
  throw_type_error(key, text, enum_names(E{}).allowed());
}

}  // namespace retreat::scenario
