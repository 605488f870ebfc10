#include "retreat/experiment/prediction.hpp"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/onset_window.hpp"
#include "retreat/core/rng.hpp"
#include "retreat/core/seed.hpp"
#include "retreat/experiment/common.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"
#include "retreat/model/population.hpp"
#include "retreat/physics/domain.hpp"
#include "retreat/physics/params.hpp"

namespace retreat::experiment {
namespace {

/// Arrivals of the chain: the arena's schedule (see predicted_population).
struct Arrivals {
  std::vector<double> times;  ///< a finite queue's robots_waiting robots [s]
  double rate = 0.0;          ///< an endless queue's Poisson arrivals [robots/s]
  std::uint32_t max_robots = 64;
};

Arrivals arrivals_of(const scenario::Scenario& s, double area) {
  Arrivals a;
  const double per_second = s.arena.lambda_in * area;
  if (s.arena.queue == physics::QueueKind::finite) {
    for (std::uint32_t k = 1; k <= s.arena.robots_waiting && per_second > 0.0; ++k) {
      a.times.push_back(static_cast<double>(k) / per_second);
    }
    a.max_robots = s.arena.robots_inside + s.arena.robots_waiting;
  } else {
    a.rate = per_second;
  }
  return a;
}

/// One robot of the chain's agent-level version: its own rule, window and entry step.
struct ChainRobot {
  std::unique_ptr<agent::Controller> rule;
  agent::OnsetWindow window;
  std::int64_t entry_step = 0;
};

}  // namespace

std::vector<double> robot_by_robot_chain(const scenario::Scenario& s, const std::string& controller, double duration,
                                         std::uint32_t runs, unsigned jobs) {
  const double area = physics::domain_of(s.arena).area();
  const double c = model::swept_rate(s.model);
  const auto& agent = s.agent;
  const Arrivals arrivals = arrivals_of(s, area);
  if (runs == 0) throw std::invalid_argument("robot_by_robot_chain: runs must be >= 1");
  const auto steps = static_cast<std::int64_t>(duration / agent.dt + 1e-9);
  const double first_decision = agent::make_controller(controller)->first_decision_after(agent);
  const double lambda_star = model::lambda_star(s.model);
  const double divisor = model::mle_divisor(s.model.delta, s.model.v, agent.L);  // as the agent's, once
  // Run `run`, its robots inside at every step added to `inside_sum`. Each run is seeded on its
  // own and the sums are integers, so the mean is the same whatever thread ran which run.
  const auto run_chain = [&](std::uint32_t run, std::vector<std::uint64_t>& inside_sum) {
    Rng rng(seed_for(s.seed, static_cast<std::int64_t>(run), Stream::world));
    std::vector<ChainRobot> inside;
    const auto enter = [&](std::int64_t step) {
      if (inside.size() < arrivals.max_robots) {
        inside.push_back(ChainRobot{agent::make_controller(controller), agent::OnsetWindow(agent.L), step});
      }
    };
    for (std::uint32_t i = 0; i < s.arena.robots_inside; ++i) enter(0);
    inside_sum[0] += inside.size();
    std::size_t next_arrival = 0;
    const PoissonDraw arrivals_in_a_step(arrivals.rate * agent.dt);
    for (std::int64_t k = 1; k <= steps; ++k) {
      const double t = static_cast<double>(k) * agent.dt;
      while (next_arrival < arrivals.times.size() && arrivals.times[next_arrival] <= t) {
        enter(k);
        ++next_arrival;
      }
      for (std::uint64_t n = arrivals_in_a_step(rng); n > 0; --n) enter(k);
      // Each robot's onsets this step: the model's encounter rate of the other N − 1 robots.
      const double others = inside.empty() ? 0.0 : static_cast<double>(inside.size() - 1);
      const PoissonDraw onsets(c * others / area * agent.dt);
      for (auto& robot : inside) robot.window.add(t, onsets(rng));
      std::erase_if(inside, [&](ChainRobot& robot) {
        const std::int64_t own = k - robot.entry_step;
        const double time_inside = static_cast<double>(own) * agent.dt;
        if (own < 1 || time_inside < first_decision - 1e-9 * agent.dt) return false;
        const std::uint64_t y = robot.window.count_at(t);
        const agent::ControllerInput input{t,        time_inside, y,     agent.L,     agent.dt,
                                           model::mle_density(y, divisor),
                                           lambda_star, s.model,  agent,       robot.window};
        return rng.uniform() < std::clamp(robot.rule->retreat_probability(input), 0.0, 1.0);
      });
      inside_sum[static_cast<std::size_t>(k)] += inside.size();
    }
  };
  // Runs in `parts` contiguous blocks, one sum each.
  const std::size_t parts = std::clamp<std::size_t>(jobs, 1, runs);
  std::vector<std::vector<std::uint64_t>> sums(parts, std::vector<std::uint64_t>(static_cast<std::size_t>(steps) + 1, 0));
  for_each_index(parts, jobs, [&](std::size_t part) {
    const auto first = static_cast<std::uint32_t>(part * runs / parts);
    const auto last = static_cast<std::uint32_t>((part + 1) * runs / parts);
    for (std::uint32_t run = first; run < last; ++run) run_chain(run, sums[part]);
  });
  std::vector<double> mean(static_cast<std::size_t>(steps) + 1, 0.0);
  for (std::size_t k = 0; k < mean.size(); ++k) {
    std::uint64_t total = 0;
    for (const auto& sum : sums) total += sum[k];
    mean[k] = static_cast<double>(total) / static_cast<double>(runs);
  }
  return mean;
}

std::optional<std::vector<double>> predicted_population(const scenario::Scenario& s, const std::string& controller,
                                                        double duration) {
  // Only a rule whose chance is a function of the window count alone (Controller::count_only):
  // the chain's N is all the state it needs.
  const auto rule = agent::make_controller(controller);
  if (!rule->count_only()) return std::nullopt;
  const double area = physics::domain_of(s.arena).area();
  const double c = model::swept_rate(s.model);
  const auto& agent = s.agent;
  const agent::OnsetWindow window(agent.L);
  const double inside = std::max(agent.L, rule->first_decision_after(agent));  // a full window

  model::PopulationChain chain;
  chain.dt = agent.dt;
  chain.first_decision = rule->first_decision_after(agent);
  chain.initial = s.arena.robots_inside;
  const Arrivals arrivals = arrivals_of(s, area);
  chain.arrival_times = arrivals.times;
  chain.arrival_rate = arrivals.rate;
  chain.max_robots = arrivals.max_robots;
  chain.leave_per_step.assign(chain.max_robots + 1, 0.0);
  for (std::uint32_t n = 1; n <= chain.max_robots; ++n) {
    const auto weights = model::poisson_weights(c * static_cast<double>(n - 1) / area * agent.L);
    double q = 0.0;
    for (std::size_t y = 0; y < weights.size(); ++y) {
      const auto onsets = static_cast<std::uint64_t>(y);
      const agent::ControllerInput input{10.0 * agent.L + inside, inside, onsets, agent.L, agent.dt,
                                         model::mle_density(onsets, s.model.delta, s.model.v, agent.L),
                                         model::lambda_star(s.model), s.model, agent, window};
      q += weights[y] * std::clamp(rule->retreat_probability(input), 0.0, 1.0);
    }
    chain.leave_per_step[n] = std::min(q, 1.0);
  }
  return model::expected_population(chain, duration);
}

}  // namespace retreat::experiment
