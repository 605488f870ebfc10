#pragma once
/// @file
/// One scenario file (YAML) describes a run. This loader reads and writes it by visiting
/// Scenario::serialize() (retreat/scenario/params.hpp); it knows no section itself. Every program
/// reads the sections it needs; every program validates the whole scenario at start-up.

#include <string>
#include <vector>

#include "retreat/scenario/params.hpp"

namespace retreat::scenario {

/// Loads a scenario: defaults, then the file, then each `section.key=value` override in order;
/// then fills the arena's copies of shared values and validates everything.
/// Throws ConfigError (missing or malformed file, unknown key, wrong type, out of range).
Scenario load(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same as load() from YAML text (for tests and in-process runs).
Scenario parse(const std::string& yaml_text, const std::vector<std::string>& overrides = {},
               const std::string& origin = "<text>");

/// Applies one `section.key=value` override (YAML scalar syntax for the value).
void apply_override(Scenario& scenario, const std::string& assignment);

/// The resolved scenario as YAML: loading it again gives the same Scenario.
std::string dump(const Scenario& scenario);

}  // namespace retreat::scenario
