#include "retreat/model/params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>

#include "retreat/model/format_number.hpp"

namespace retreat::model {
namespace {

/// Throws unless @p value is finite and > 0; the message is the scenario file's `model.<field>`.
void require_positive(std::string_view field, double value, std::string_view unit) {
  if (std::isfinite(value) && value > 0.0) {
    return;
  }
  const std::string range = std::isfinite(value) ? "> 0" : "finite and > 0";
  throw std::invalid_argument("model." + std::string(field) + " = " + format_number(value) +
                              ": must be " + range + " (" + std::string(unit) + ")");
}

}  // namespace

void ModelParams::validate() const {
  require_positive("lambda_p", lambda_p, "1/m^2");
  require_positive("lambda_d", lambda_d, "1/m^2");
  require_positive("C", C, "dimensionless");
  require_positive("delta", delta, "m");
  require_positive("v", v, "m/s");
  require_positive("rho", rho, "1/s");
}

}  // namespace retreat::model
