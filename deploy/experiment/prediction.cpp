#include "prediction.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>

#include "retreat/agent/controller_registry.hpp"
#include "retreat/agent/onset_window.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/population.hpp"
#include "retreat/physics/domain.hpp"

namespace retreat::experiment {
namespace {

/// The rules whose chance at a step is a function of the window count alone (and the
/// configured parameters): the chain's N is all the state they need.
constexpr std::array<std::string_view, 4> count_only_rules = {"paper", "confident", "confident-proportional",
                                                             "influx-matching"};

double area_of(const physics::WorldParams& a) {
  return a.shape == physics::DomainShape::ellipse ? physics::Domain::ellipse(a.semi_axis_x, a.semi_axis_y).area()
                                                  : physics::Domain::rectangle(a.width, a.height).area();
}

}  // namespace

std::optional<std::vector<double>> predicted_population(const scenario::Scenario& s, const std::string& controller,
                                                        double duration) {
  if (std::find(count_only_rules.begin(), count_only_rules.end(), controller) == count_only_rules.end()) {
    return std::nullopt;
  }
  const double area = area_of(s.arena);
  const double c = model::swept_rate(s.model);
  const auto& agent = s.agent;
  const auto rule = agent::make_controller(controller);
  const agent::OnsetWindow window(agent.L);
  const double inside = std::max(agent.L, rule->first_decision_after(agent));  // a full window

  model::PopulationChain chain;
  chain.dt = agent.dt;
  chain.first_decision = rule->first_decision_after(agent);
  chain.initial = s.arena.robots_inside;
  const double arrivals_per_second = s.arena.lambda_in * area;
  if (s.arena.queue == physics::QueueKind::finite) {
    for (std::uint32_t k = 1; k <= s.arena.robots_waiting && arrivals_per_second > 0.0; ++k) {
      chain.arrival_times.push_back(static_cast<double>(k) / arrivals_per_second);
    }
    chain.max_robots = s.arena.robots_inside + s.arena.robots_waiting;
  } else {
    chain.arrival_rate = arrivals_per_second;
    chain.max_robots = 64;
  }
  chain.leave_per_step.assign(chain.max_robots + 1, 0.0);
  for (std::uint32_t n = 1; n <= chain.max_robots; ++n) {
    const auto weights = model::poisson_weights(c * static_cast<double>(n - 1) / area * agent.L);
    double q = 0.0;
    for (std::size_t y = 0; y < weights.size(); ++y) {
      const auto onsets = static_cast<std::uint64_t>(y);
      const agent::ControllerInput input{10.0 * agent.L + inside, inside, onsets, agent.L, agent.dt,
                                         model::mle_density(onsets, s.model.delta, s.model.v, agent.L),
                                         s.model, agent, window};
      q += weights[y] * std::clamp(rule->retreat_probability(input), 0.0, 1.0);
    }
    chain.leave_per_step[n] = std::min(q, 1.0);
  }
  return model::expected_population(chain, duration);
}

}  // namespace retreat::experiment
