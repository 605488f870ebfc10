#pragma once
/// @file
/// What the population chain of retreat::model (population.hpp) predicts for a rule on a
/// scenario: the mean-field prediction the controllers' measurements are set against.

#include <optional>
#include <string>
#include <vector>

#include "retreat/scenario/params.hpp"

namespace retreat::experiment {

/// E[robots inside] at t = k·dt (the agents' dt), k = 0 .. duration/dt, for `controller` on
/// scenario `s`, from the population chain with:
///   - each robot's chance per step at N robots inside = the rule's probability averaged over
///     its window count y ~ Poisson(c·(N − 1)/|D| · L) (the model's encounter rate of the
///     other N − 1 robots, MODEL.md §2 and §7.1; a full window), computed by calling the rule;
///   - arrivals as the arena schedules them: robots_waiting robots at k/(λ_in|D|) with a finite
///     queue, Poisson at λ_in|D| with an endless one (the arena's λ_in);
///   - nobody leaving before the rule's first decision (L for `paper`).
/// nullopt for a rule whose chance depends on more than its window count (`influx-aware`
/// reads its own history), for which the chain has no state to stand on.
std::optional<std::vector<double>> predicted_population(const scenario::Scenario& s, const std::string& controller,
                                                        double duration);

}  // namespace retreat::experiment
