#include "retreat/agent/controller_registry.hpp"

#include <array>
#include <stdexcept>

#include "retreat/agent/adaptive_proportional_controller.hpp"
#include "retreat/agent/confident_controller.hpp"
#include "retreat/agent/early_confident_controllers.hpp"
#include "retreat/agent/influx_aware_controller.hpp"
#include "retreat/agent/paper_controller.hpp"

namespace retreat::agent {
namespace {

struct Registration {
  std::string_view name;
  std::unique_ptr<Controller> (*make)();
};

template <typename C>
std::unique_ptr<Controller> make() {
  return std::make_unique<C>();
}

std::unique_ptr<Controller> make_confident_influx_aware() {
  return std::make_unique<InfluxAwareController>(ConfidentController::default_z,
                                                 InfluxAwareController::confident_name);
}

// Every controller, one line each. A new controller is a new file plus one line here.
constexpr std::array registry{
    Registration{PaperController::registered_name, &make<PaperController>},
    Registration{ConfidentController::registered_name, &make<ConfidentController>},
    Registration{InfluxAwareController::registered_name, &make<InfluxAwareController>},
    Registration{InfluxAwareController::confident_name, &make_confident_influx_aware},
    Registration{ConfidentProportionalController::registered_name,
                 &make<ConfidentProportionalController>},
    Registration{InfluxMatchingController::registered_name, &make<InfluxMatchingController>},
    Registration{AdaptiveProportionalController::registered_name,
                 &make<AdaptiveProportionalController>},
};

const Registration* find(std::string_view name) {
  for (const Registration& entry : registry) {
    if (entry.name == name) {
      return &entry;
    }
  }
  return nullptr;
}

}  // namespace

std::unique_ptr<Controller> make_controller(std::string_view name) {
  if (const Registration* entry = find(name)) {
    return entry->make();
  }
  std::string valid;
  for (const Registration& entry : registry) {
    valid += (valid.empty() ? "" : ", ") + std::string(entry.name);
  }
  throw std::invalid_argument("agent.controller = '" + std::string(name) + "': must be one of " +
                              valid);
}

std::vector<std::string> controller_names() {
  std::vector<std::string> names;
  names.reserve(registry.size());
  for (const Registration& entry : registry) {
    names.emplace_back(entry.name);
  }
  return names;
}

bool is_controller_name(std::string_view name) { return find(name) != nullptr; }

}  // namespace retreat::agent
