#include "retreat/agent/agent_params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/model/format_number.hpp"

namespace retreat::agent {
namespace {

using model::format_number;

[[noreturn]] void reject(std::string_view field, double value, std::string_view range,
                         std::string_view unit) {
  throw std::invalid_argument("agent." + std::string(field) + " = " + format_number(value) +
                              ": must be " + std::string(range) + " (" + std::string(unit) + ")");
}

void require_positive(std::string_view field, double value, std::string_view unit) {
  if (!std::isfinite(value)) {
    reject(field, value, "finite and > 0", unit);
  }
  if (!(value > 0.0)) {
    reject(field, value, "> 0", unit);
  }
}

void require_non_negative(std::string_view field, double value, std::string_view unit) {
  if (!std::isfinite(value)) {
    reject(field, value, "finite and >= 0", unit);
  }
  if (!(value >= 0.0)) {
    reject(field, value, ">= 0", unit);
  }
}

}  // namespace

void AgentParams::validate() const {
  require_positive("L", L, "s");
  const std::string dt_range = "> 0 and <= agent.L (" + format_number(L) + ")";
  if (!std::isfinite(dt)) {
    reject("dt", dt, "finite and " + dt_range, "s");
  }
  if (!(dt > 0.0 && dt <= L)) {
    reject("dt", dt, dt_range, "s");
  }
  require_non_negative("K_p", K_p, "1/s");
  require_non_negative("lambda_in", lambda_in, "robots/(m^2 s)");
  if (!(std::isfinite(missed_onsets) && missed_onsets >= 0.0 && missed_onsets < 1.0)) {
    reject("missed_onsets", missed_onsets, "in [0, 1)", "chance per onset");
  }
  require_non_negative("false_onsets", false_onsets, "1/s");
  if (!is_controller_name(controller)) {
    std::string valid;
    for (const std::string& name : controller_names()) {
      valid += (valid.empty() ? "" : ", ") + name;
    }
    throw std::invalid_argument("agent.controller = '" + controller + "': must be one of " + valid);
  }
}

}  // namespace retreat::agent
