#pragma once
/// @file
/// Controllers by name: the only place that knows every controller.

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "retreat/agent/controller.hpp"

namespace retreat::agent {

/// A new controller of the registered kind @p name.
/// @throws std::invalid_argument for an unknown name; the message lists the valid names:
///         `agent.controller = 'foo': must be one of paper`.
std::unique_ptr<Controller> make_controller(std::string_view name);

/// Every registered controller name, in registration order (`paper` first).
std::vector<std::string> controller_names();

/// Whether @p name is a registered controller name.
bool is_controller_name(std::string_view name);

}  // namespace retreat::agent
