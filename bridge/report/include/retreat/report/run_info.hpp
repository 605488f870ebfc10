#pragma once
/// @file
/// The facts of a run the bridge compares against (λ*, |D|, the domain's outline), from a
/// scenario.

#include "retreat/scenario/scenario.hpp"
#include "retreat/telemetry/aggregator.hpp"

namespace retreat::report {

/// λ* from retreat::model::lambda_star, |D| from retreat::physics::Domain, the rest copied.
telemetry::RunInfo run_info(const scenario::Scenario& s);

}  // namespace retreat::report
