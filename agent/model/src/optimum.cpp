#include "retreat/model/optimum.hpp"

#include <cmath>

#include "retreat/model/ctmc.hpp"

namespace retreat::model {

double cost(const ModelParams& p, double lambda) { return p.C / output(p, lambda) + lambda; }

double lambda_star(const ModelParams& p) {
  return std::sqrt(p.C * (1.0 + p.lambda_d / p.lambda_p) / (2.0 * p.delta * p.v * p.lambda_d));
}

}  // namespace retreat::model
