#include "retreat/agent/early_confident_controllers.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/agent/confident_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

double counted_span(const ControllerInput& input) { return std::min(input.time_inside, input.L); }

double confident_partial_density(const ControllerInput& input, double z) {
  return confident_density(input.onsets_in_window, counted_span(input), input, z);
}

double confident_density(std::uint64_t onsets, double span, const ControllerInput& input, double z) {
  const double m = input.agent.missed_onsets;
  const double f = input.agent.false_onsets;
  if (m == 0.0 && f == 0.0) {
    return lower_confidence_density(onsets, input.model, span, z);
  }
  check_confidence_z(z);
  // The lowered count, less the spurious onsets expected over the span, over the kept fraction.
  const double y = static_cast<double>(onsets);
  const double low_count = std::max(0.0, y - z * std::sqrt(y));
  return std::max(0.0, low_count - f * span) / ((1.0 - m) * model::swept_rate(input.model) * span);
}

ConfidentProportionalController::ConfidentProportionalController(double z) : z_(z) {
  check_confidence_z(z);
}

double ConfidentProportionalController::retreat_probability(const ControllerInput& input) {
  const double lambda_low = confident_partial_density(input, z_);
  const double rate =
      model::epsilon(lambda_low, input.lambda_star, 0.0, input.agent.K_p);
  return rate * input.dt;
}

InfluxMatchingController::InfluxMatchingController(double z) : proportional_(z) {}

double InfluxMatchingController::retreat_probability(const ControllerInput& input) {
  // λ* > 0: the model's parameters are validated (C, δ, v, λ_p, λ_d > 0).
  const double matching = input.agent.lambda_in / input.lambda_star;
  return matching * input.dt + proportional_.retreat_probability(input);
}

}  // namespace retreat::agent
