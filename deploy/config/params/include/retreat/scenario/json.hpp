#pragma once
/// @file
/// A scenario as JSON, for builds without yaml-cpp (a Clang + libc++ build of the core reads its
/// scenarios this way). The same sections and keys as the YAML file, by visiting
/// Scenario::serialize(); names (`arena.shape`, `run.mode`, ...) are JSON strings, numbers JSON
/// numbers. Reading validates exactly as the YAML loader does and gives the same Scenario.

#include <string>

#include "retreat/scenario/params.hpp"

namespace retreat::scenario {

/// Reads a scenario from JSON text: defaults, then the text; then resolve() and validate().
/// Throws ConfigError (malformed JSON, unknown key, wrong type, out of range), one line each.
Scenario parse_json(const std::string& json_text, const std::string& origin = "<json>");

/// Same as parse_json() from a file.
Scenario load_json(const std::string& path);

/// The scenario as JSON, keys in file order: parse_json() of it gives the same Scenario.
std::string dump_json(const Scenario& scenario);

}  // namespace retreat::scenario
