#include "retreat/agent/confident_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "retreat/model/control.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

/// One line for a bad z.
void check_confidence_z(double z) {
  if (!std::isfinite(z) || z < 0.0) {
    throw std::invalid_argument("confidence z = " + std::to_string(z) +
                                ": must be finite and >= 0");
  }
}

ConfidentController::ConfidentController(double z) : z_(z) { check_confidence_z(z); }

double lower_confidence_density(std::uint64_t onsets, const model::ModelParams& model, double L,
                                double z) {
  check_confidence_z(z);
  const double y = static_cast<double>(onsets);
  return std::max(0.0, y - z * std::sqrt(y)) / (model::swept_rate(model) * L);
}

double ConfidentController::retreat_probability(const ControllerInput& input) {
  const double lambda_low =
      lower_confidence_density(input.onsets_in_window, input.model, input.L, z_);
  const double rate = model::epsilon(lambda_low, input.lambda_star,
                                     input.agent.lambda_in, input.agent.K_p);
  return rate * input.dt;
}

}  // namespace retreat::agent
