#include "retreat/agent/early_confident_controllers.hpp"

#include <algorithm>
#include <cmath>

#include "retreat/agent/confident_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

double counted_span(const ControllerInput& input) { return std::min(input.time_inside, input.L); }

double confident_partial_density(const ControllerInput& input, double z) {
  return lower_confidence_density(input.onsets_in_window, input.model, counted_span(input), z);
}

ConfidentProportionalController::ConfidentProportionalController(double z) : z_(z) {
  lower_confidence_density(0, model::ModelParams{}, 1.0, z);  // checks z
}

double ConfidentProportionalController::retreat_probability(const ControllerInput& input) {
  const double lambda_low = confident_partial_density(input, z_);
  const double rate =
      model::epsilon(lambda_low, model::lambda_star(input.model), 0.0, input.agent.K_p);
  return rate * input.dt;
}

InfluxMatchingController::InfluxMatchingController(double z) : proportional_(z) {}

double InfluxMatchingController::retreat_probability(const ControllerInput& input) {
  // λ* > 0: the model's parameters are validated (C, δ, v, λ_p, λ_d > 0).
  const double matching = input.agent.lambda_in / model::lambda_star(input.model);
  return matching * input.dt + proportional_.retreat_probability(input);
}

}  // namespace retreat::agent
