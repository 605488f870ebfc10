#include "retreat/agent/influx_aware_controller.hpp"

#include <algorithm>
#include <cstddef>

#include "retreat/agent/confident_controller.hpp"
#include "retreat/model/control.hpp"
#include "retreat/model/optimum.hpp"

namespace retreat::agent {

InfluxAwareController::InfluxAwareController(double z, std::string_view name)
    : z_(z), name_(name) {
  check_confidence_z(z);
}

double InfluxAwareController::retreat_probability(const ControllerInput& input) {
  const double t = input.time;
  const double past_limit = t - input.L + 1e-9 * input.dt;  // absorbs k·dt rounding

  // Keep exactly one step at or before t − L (the reference), drop the older ones.
  while (steps_.size() >= 2 && steps_[1].time <= past_limit) {
    outflow_sum_ -= steps_[1].outflow;
    steps_.pop_front();
  }

  double influx = 0.0;  // no earlier window yet: no evidence of an influx
  if (!steps_.empty() && steps_.front().time <= past_limit) {
    const Step& past = steps_.front();
    const double trend = (input.lambda_hat - past.lambda_hat) / (t - past.time);
    const std::size_t n = steps_.size() - 1;  // steps in (t − L, t)
    const double outflow = n > 0 ? outflow_sum_ / static_cast<double>(n) : 0.0;
    influx = std::clamp(trend + outflow, 0.0, input.agent.lambda_in);
  }
  last_influx_ = influx;

  const double lambda = z_ > 0.0 ? lower_confidence_density(input.onsets_in_window, input.model,
                                                            input.L, z_)
                                 : input.lambda_hat;
  const double rate =
      model::epsilon(lambda, input.lambda_star, influx, input.agent.K_p);
  const double outflow = std::min(rate, 1.0 / input.dt) * input.lambda_hat;
  steps_.push_back({t, input.lambda_hat, outflow});
  if (steps_.size() >= 2) {
    outflow_sum_ += outflow;
  }
  return rate * input.dt;
}

}  // namespace retreat::agent
