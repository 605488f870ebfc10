#pragma once
// The table of scenario keys: one entry per key, binding it to a struct member.

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "retreat/scenario/scenario.hpp"

namespace retreat::scenario::detail {

struct Field {
  std::string key;  ///< `section.key` or a top-level `key`
  std::function<void(Scenario&, const YAML::Node&)> read;
  std::function<void(const Scenario&, YAML::Emitter&)> write;
};

/// Every field, in the order dump() writes them.
const std::vector<Field>& fields();

}  // namespace retreat::scenario::detail
