#pragma once
/// @file
/// The population of a regulated swarm as a Markov chain over the number of robots inside D:
/// the prediction a density-regulation rule is compared against (issue 14, docs/experiments.md).

#include <cstdint>
#include <vector>

namespace retreat::model {

/// A swarm seen as the number N of robots inside D, stepped every `dt`:
///
/// - at the start of a step, arrivals: one robot at each time in `arrival_times` that falls in
///   the step, and additionally a Poisson number with mean `arrival_rate`·dt (an endless queue);
/// - then each of the N robots leaves independently with probability `leave_per_step[N]` (the
///   robots' rule averaged over what a robot among N sees; 0 for N beyond the vector), but only
///   from `first_decision` on (the rule's wait before its first decision, counted from t = 0).
///
/// This is the mean-field assumption of MODEL.md §5 made discrete: a robot's chance depends on
/// the population only, not on its own history or age.
struct PopulationChain {
  std::uint32_t initial = 0;                ///< robots inside at t = 0
  std::vector<double> arrival_times;        ///< deterministic arrivals [s], ascending
  double arrival_rate = 0.0;                ///< Poisson arrivals [robots/s], >= 0
  std::vector<double> leave_per_step;       ///< index N: each robot's chance per step [-], in [0, 1]
  double dt = 0.03;                         ///< step [s], > 0
  double first_decision = 0.0;              ///< no robot leaves before this time [s]
  std::uint32_t max_robots = 64;            ///< N is capped here (arrivals beyond it are lost)
};

/// The expected number of robots inside, E[N(t)], at t = k·dt for k = 0 .. duration/dt, by
/// propagating the distribution of N exactly (binomial departures, Poisson arrivals truncated
/// at max_robots).
/// @throws std::invalid_argument if dt or duration is not finite and > 0, arrival_rate is
///         negative, or a leave probability lies outside [0, 1].
std::vector<double> expected_population(const PopulationChain& chain, double duration);

/// The time-mean of @p series (values at k·dt) over [from, to], from the samples in the span.
double time_mean(const std::vector<double>& series, double dt, double from, double to);

/// P(Y = y) for Y ~ Poisson(mean), y = 0 .. up to the first y past the mean whose tail is below
/// 1e-15 (the weights sum to 1 within that) [-].
std::vector<double> poisson_weights(double mean);

}  // namespace retreat::model
