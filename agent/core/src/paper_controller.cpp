#include "retreat/agent/paper_controller.hpp"

#include "retreat/model/control.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

double PaperController::retreat_probability(const ControllerInput& input) {
  const double rate = model::epsilon(input.lambda_hat, input.lambda_star,
                                     input.agent.lambda_in, input.agent.K_p);
  return rate * input.dt;
}

}  // namespace retreat::agent
