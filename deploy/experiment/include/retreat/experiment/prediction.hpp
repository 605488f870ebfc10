#pragma once
/// @file
/// What the population chain of retreat::model (population.hpp) predicts for a rule on a
/// scenario: the mean-field prediction the controllers' measurements are set against.

#include <cstdint>
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
/// nullopt for a rule whose chance depends on more than its window count (`influx-aware`,
/// `confident-influx-aware` and `adaptive-proportional` read their own history), for which the
/// chain has no state to stand on: robot_by_robot_chain predicts those.
std::optional<std::vector<double>> predicted_population(const scenario::Scenario& s, const std::string& controller,
                                                        double duration);

/// The same chain run robot by robot, for any rule: every robot inside gets Poisson onsets at
/// c·(N(t) − 1)/|D| per second (N(t) the robots inside at that step) into its own OnsetWindow
/// and its own instance of the rule, decides at the agent's steps (from the rule's first
/// decision after its own entry) and leaves on a coin; arrivals as above. It keeps what the
/// chain averages away: each robot's age and a window that holds the past L seconds of a
/// changing N (the lag that makes `paper` overshoot), and it predicts rules with memory. No
/// space, no physics: only the encounter model. E[robots inside] at each step, the mean over
/// @p runs runs seeded from s.seed (the same numbers every time, whatever @p jobs is: the
/// threads the runs are shared among).
/// @throws std::invalid_argument if @p runs is 0.
std::vector<double> robot_by_robot_chain(const scenario::Scenario& s, const std::string& controller, double duration,
                                         std::uint32_t runs, unsigned jobs = 1);

}  // namespace retreat::experiment
