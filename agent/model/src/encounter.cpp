#include "retreat/model/encounter.hpp"

namespace retreat::model {
namespace {

// π; std::numbers::pi would need C++20 and the libraries are written to C++17.
constexpr double pi = 3.141592653589793238462643383279502884;

}  // namespace

double relative_speed(double v) { return 4.0 / pi * v; }

double swept_rate(const ModelParams& p) { return 4.0 * p.delta * relative_speed(p.v); }

double omega_c(const ModelParams& p, double lambda) { return swept_rate(p) * lambda; }

double omega_p(const ModelParams& p) { return 2.0 * p.delta * p.v * p.lambda_p; }

double omega_d(const ModelParams& p) { return 2.0 * p.delta * p.v * p.lambda_d; }

}  // namespace retreat::model
