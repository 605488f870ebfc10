#include "retreat/model/control.hpp"

namespace retreat::model {

// NOLINTNEXTLINE(readability-identifier-naming): K_p is the paper's symbol.
double epsilon(double lambda, double lambda_star, double lambda_in, double K_p) {
  if (!(lambda > lambda_star)) {  // also 0 for a NaN estimate: never retreat on garbage
    return 0.0;
  }
  return (lambda_in - K_p * (lambda_star - lambda)) / lambda;
}

}  // namespace retreat::model
