#include "retreat/physics/params.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "retreat/physics/domain.hpp"
#include "retreat/physics/types.hpp"

namespace retreat::physics {
namespace {

constexpr double pi = 3.14159265358979323846;

/// Shortest text that reads back as @p value.
std::string text(double value) {
  if (std::isnan(value)) {
    return "nan";
  }
  if (std::isinf(value)) {
    return value > 0 ? "inf" : "-inf";
  }
  char buffer[64];
  // A whole number is written out (1000000, not 1e+06) while that is short enough to read.
  const bool whole = std::abs(value) < 1e15 && value == std::trunc(value);
  const auto result = whole ? std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed)
                            : std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

[[noreturn]] void reject(std::string_view key, const std::string& value, const std::string& rule) {
  throw std::invalid_argument(std::string(key) + " = " + value + ": " + rule);
}

void require(bool ok, std::string_view key, double value, const std::string& rule) {
  if (!ok) {
    reject(key, text(value), rule);
  }
}

void require_positive(std::string_view key, double value, std::string_view unit) {
  require(std::isfinite(value) && value > 0.0, key, value,
          "must be finite and > 0 (" + std::string(unit) + ")");
}

void require_non_negative(std::string_view key, double value, std::string_view unit) {
  require(std::isfinite(value) && value >= 0.0, key, value,
          "must be finite and >= 0 (" + std::string(unit) + ")");
}

/// An enum member holds one of its named values (a loader only sets named ones; a cast may not).
template <class E>
void require_named(std::string_view key, E value) {
  if (!enum_names(value).find(name_of(value))) {
    reject(key, std::to_string(static_cast<int>(value)), "must be " + enum_names(value).allowed());
  }
}


}  // namespace

std::string_view to_string(Phase phase) {
  switch (phase) {
    case Phase::waiting:
      return "waiting";
    case Phase::inside:
      return "inside";
    case Phase::retreating:
      return "retreating";
    case Phase::departed:
      return "departed";
  }
  return "?";
}

std::string_view to_string(TaskState state) {
  switch (state) {
    case TaskState::f:
      return "f";
    case TaskState::l:
      return "l";
    case TaskState::fc:
      return "fc";
    case TaskState::lc:
      return "lc";
  }
  return "?";
}

std::int64_t substeps_per_tick(const WorldParams& params) {
  return std::llround(params.tick_dt / params.physics_dt);
}

double walk_inset(const WorldParams& params) {
  return params.robot_radius + params.projection_distance +
         params.v * (2.0 * params.physics_dt + 1.0 / params.boundary_gain);
}

Domain domain_of(const WorldParams& params) {
  return params.shape == DomainShape::ellipse ? Domain::ellipse(params.semi_axis_x, params.semi_axis_y)
                                              : Domain::rectangle(params.width, params.height);
}

namespace {

/// max_robots of @p params, whose domain_of is @p domain (built once by validate()).
std::uint32_t max_robots_in(const WorldParams& params, const Domain& domain) {
  const double disc = pi * 0.25 * params.safety_distance * params.safety_distance;
  const double walkable = domain.inset_area(params.robot_radius + params.projection_distance);
  // In double first: a large arena holds more robots than a std::uint32_t counts.
  const double fit = std::floor(0.4 * walkable / disc);
  constexpr double most = std::numeric_limits<std::uint32_t>::max();
  return fit >= most ? std::numeric_limits<std::uint32_t>::max() : static_cast<std::uint32_t>(fit);
}

}  // namespace

std::uint32_t max_robots(const WorldParams& params) { return max_robots_in(params, domain_of(params)); }

void WorldParams::validate() const {
  require_named("arena.encounter_model", encounter_model);
  require_named("arena.shape", shape);
  require_named("arena.queue", queue);
  require_named("arena.influx", influx);
  const EncounterModel model = encounter_model;
  const DomainShape domain_shape = shape;
  const QueueKind queue_kind = queue;

  // Robot and model numbers first: the domain checks below use them.
  require_positive("arena.robot_radius", robot_radius, "m");
  require_positive("model.delta", delta, "m");
  require(delta > robot_radius, "model.delta", delta,
          "must be > arena.robot_radius (" + text(robot_radius) +
              " m): the sensing skirt must reach beyond the footprint");
  require_positive("arena.safety_distance", safety_distance, "m");
  require(safety_distance >= 2.0 * robot_radius, "arena.safety_distance", safety_distance,
          "must be >= 2 * arena.robot_radius (" + text(2.0 * robot_radius) +
              " m) or footprints may overlap");
  if (model == EncounterModel::physical) {
    require(2.0 * delta > safety_distance, "model.delta", delta,
            "must be > arena.safety_distance / 2 (" + text(0.5 * safety_distance) +
                " m) or no two robots can ever come within 2 delta");
  }
  require_positive("model.v", v, "m/s");
  require_positive("arena.max_speed", max_speed, "m/s");
  require(v <= max_speed, "model.v", v, "must be <= arena.max_speed (" + text(max_speed) + " m/s)");
  require_positive("arena.projection_distance", projection_distance, "m");
  require(projection_distance < robot_radius + delta, "arena.projection_distance",
          projection_distance,
          "must be < arena.robot_radius + model.delta (" + text(robot_radius + delta) + " m)");
  require_positive("arena.max_turn_rate", max_turn_rate, "rad/s");
  if (model == EncounterModel::physical) {
    require(v <= projection_distance * max_turn_rate * (1.0 + 1e-12), "arena.max_turn_rate",
            max_turn_rate,
            "must be >= model.v / arena.projection_distance (" + text(v / projection_distance) +
                " rad/s) so that the projected point can move at speed v in any direction");
  }
  require_non_negative("model.lambda_p", lambda_p, "1/m^2");
  require_non_negative("model.lambda_d", lambda_d, "1/m^2");
  if (model == EncounterModel::kinetic) {
    require_positive("model.rho", rho, "1/s");
  }

  // Time.
  require_positive("agent.dt", tick_dt, "s");
  require_positive("arena.physics_dt", physics_dt, "s");
  require(physics_dt <= tick_dt, "arena.physics_dt", physics_dt,
          "must be <= agent.dt (" + text(tick_dt) + " s)");
  const double ratio = tick_dt / physics_dt;
  require(std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio, "arena.physics_dt", physics_dt,
          "must divide agent.dt (" + text(tick_dt) + " s) into a whole number of steps");
  require(std::round(ratio) <= max_substeps_per_tick, "arena.physics_dt", physics_dt,
          "must be >= agent.dt / " + text(max_substeps_per_tick) + " (" +
              text(tick_dt / max_substeps_per_tick) + " s): at most " + text(max_substeps_per_tick) +
              " physics steps per tick");
  if (model == EncounterModel::physical) {
    require(max_speed * physics_dt <= 0.25 * delta, "arena.physics_dt", physics_dt,
            "must be <= model.delta / (4 * arena.max_speed) (" + text(0.25 * delta / max_speed) +
                " s) so that encounters are resolved");
    require(max_turn_rate * physics_dt <= 0.5, "arena.physics_dt", physics_dt,
            "must be <= 0.5 / arena.max_turn_rate (" + text(0.5 / max_turn_rate) + " s)");
  }
  require_positive("arena.gamma", gamma, "1/(m^4 s)");
  require_positive("arena.boundary_gain", boundary_gain, "1/s");
  if (model == EncounterModel::physical) {
    require(boundary_gain * physics_dt <= 1.0, "arena.boundary_gain", boundary_gain,
            "must be <= 1 / arena.physics_dt (" + text(1.0 / physics_dt) + " 1/s)");
  }
  require_non_negative("arena.tumble_rate", tumble_rate, "1/s");
  // Rates whose events the world draws one by one within a tick.
  const auto events = [&](std::string_view key, double value, double per_tick, std::string_view what) {
    require(per_tick <= max_events_per_tick, key, value,
            "must be <= " + text(value * max_events_per_tick / per_tick) + ": at most " + text(max_events_per_tick) +
                " " + std::string(what) + " expected per robot per tick (agent.dt = " + text(tick_dt) + " s)");
  };
  if (model == EncounterModel::physical) {
    events("arena.tumble_rate", tumble_rate, tumble_rate * tick_dt, "tumbles");
  } else {
    events("model.lambda_p", lambda_p, 2.0 * delta * v * lambda_p * tick_dt, "pick-ups");
    events("model.lambda_d", lambda_d, 2.0 * delta * v * lambda_d * tick_dt, "drop-offs");
  }
  require_positive("arena.unblock_time", unblock_time, "s");
  require_non_negative("agent.lambda_in", lambda_in, "robots/(m^2 s)");
  require(std::isfinite(missed_onsets) && missed_onsets >= 0.0 && missed_onsets <= 1.0, "arena.missed_onsets",
          missed_onsets, "must be in [0, 1] (a probability per onset)");
  require_non_negative("arena.false_onsets", false_onsets, "1/s");
  if (external_robots > 0) {
    require(model == EncounterModel::physical, "arena.external_robots", external_robots,
            "must be 0 with arena.encounter_model = kinetic (a real robot needs positions)");
    require(external_robots <= robots_inside, "arena.external_robots", external_robots,
            "must be <= arena.robots_inside (" + std::to_string(robots_inside) +
                "): real robots are robots 0 .. external_robots-1 and start inside");
  }
  require_positive("arena.external_frozen_after", external_frozen_after, "s");
  require(std::isfinite(external_lost_after) && external_lost_after >= external_frozen_after,
          "arena.external_lost_after", external_lost_after,
          "must be >= arena.external_frozen_after (" + text(external_frozen_after) + " s)");
  require_positive("arena.external_max_speed", external_max_speed, "m/s");

  // Domain.
  const double inset = walk_inset(*this);
  const std::string too_large = "must be <= " + text(max_extent) +
                                " m (a larger arena leaves a double too coarse for a physics step)";
  if (domain_shape == DomainShape::ellipse) {
    require_positive("arena.semi_axis_x", semi_axis_x, "m");
    require_positive("arena.semi_axis_y", semi_axis_y, "m");
    require(semi_axis_x <= max_extent, "arena.semi_axis_x", semi_axis_x, too_large);
    require(semi_axis_y <= max_extent, "arena.semi_axis_y", semi_axis_y, too_large);
    require(semi_axis_x > 2.0 * inset, "arena.semi_axis_x", semi_axis_x,
            "must be > " + text(2.0 * inset) + " m (twice the walk inset r + l + margin)");
    require(semi_axis_y > 2.0 * inset, "arena.semi_axis_y", semi_axis_y,
            "must be > " + text(2.0 * inset) + " m (twice the walk inset r + l + margin)");
  } else {
    require_positive("arena.width", width, "m");
    require_positive("arena.height", height, "m");
    require(width <= max_extent, "arena.width", width, too_large);
    require(height <= max_extent, "arena.height", height, too_large);
    require(width > 4.0 * inset, "arena.width", width,
            "must be > " + text(4.0 * inset) + " m (four times the walk inset r + l + margin)");
    require(height > 4.0 * inset, "arena.height", height,
            "must be > " + text(4.0 * inset) + " m (four times the walk inset r + l + margin)");
  }

  // Population.
  if (queue_kind == QueueKind::endless) {
    require(robots_waiting >= 1, "arena.robots_waiting", robots_waiting,
            "must be >= 1 with arena.queue = endless (the length of the visible queue)");
  }
  require(static_cast<double>(robots_inside) + robots_waiting >= 1.0, "arena.robots_inside",
          robots_inside, "must be >= 1 when arena.robots_waiting = 0");
  const Domain domain = domain_of(*this);  // its perimeter sums 4,096 points: built once
  const std::uint32_t fit = max_robots_in(*this, domain);
  require(robots_inside <= fit, "arena.robots_inside", robots_inside,
          "must be <= " + std::to_string(fit) +
              ": safety discs (diameter arena.safety_distance) may cover at most 40 % of the "
              "walkable area");
  if (queue_kind == QueueKind::finite) {
    require(static_cast<double>(robots_inside) + robots_waiting <= fit, "arena.robots_waiting",
            robots_waiting,
            "must be <= " + std::to_string(fit - robots_inside) +
                " (robots_inside + robots_waiting may all be inside at once; at most " +
                std::to_string(fit) + " fit)");
  }
  require(robots_inside <= max_start_robots, "arena.robots_inside", robots_inside,
          "must be <= " + std::to_string(max_start_robots) + " (robots a run starts with)");
  require(static_cast<double>(robots_inside) + robots_waiting <= max_start_robots, "arena.robots_waiting",
          robots_waiting,
          "must be <= " + std::to_string(max_start_robots - robots_inside) + " (robots_inside + robots_waiting, " +
              "the robots a run starts with, each with its agent, at most " + std::to_string(max_start_robots) + ")");

  const double area = domain.area();
  // Arrivals: the influx draws them one by one, whatever the queue (a finite one drops those
  // with nobody left to send).
  require(lambda_in * area * tick_dt <= max_arrivals_per_tick, "agent.lambda_in", lambda_in,
          "must be <= " + text(max_arrivals_per_tick / (area * tick_dt)) + " robots/(m^2 s) in this arena (|D| = " +
              text(area) + " m^2): at most " + text(max_arrivals_per_tick) + " arrivals expected per tick (agent.dt = " +
              text(tick_dt) + " s)");

  // Task locations (physical world): each is a point the world holds for the whole run.
  if (model == EncounterModel::physical) {
    const auto locations = [&](std::string_view key, double density, std::string_view what) {
      require(density * area <= max_task_locations, key, density,
              "must be <= " + text(max_task_locations / area) + " 1/m^2 in this arena (|D| = " + text(area) +
                  " m^2): at most " + text(max_task_locations) + " " + std::string(what) + " locations");
    };
    locations("model.lambda_p", lambda_p, "pick-up");
    locations("model.lambda_d", lambda_d, "drop-off");
  }
}

}  // namespace retreat::physics
