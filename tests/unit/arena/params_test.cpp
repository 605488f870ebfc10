// WorldParams::validate(): every bad field is named with its key and value.

#include "retreat/physics/params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

struct BadCase {
  std::string prefix;  // the message must start with "<key> = <value>:"
  std::function<void(WorldParams&)> spoil;
};

std::string message_of(const WorldParams& p) {
  try {
    p.validate();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "(no exception)";
}

TEST(PhysicsParams, DefaultsAreValidForBothEncounterModels) {
  WorldParams p;
  EXPECT_NO_THROW(p.validate());
  p.encounter_model = EncounterModel::kinetic;
  EXPECT_NO_THROW(p.validate());
}

TEST(PhysicsParams, EachInvalidFieldIsRejectedWithItsKeyAndValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<BadCase> cases = {
      // Names are checked by the scenario loader; here only a value cast outside the enum.
      {"arena.encounter_model = 9:",
       [](WorldParams& p) { p.encounter_model = static_cast<EncounterModel>(9); }},
      {"arena.shape = 9:", [](WorldParams& p) { p.shape = static_cast<DomainShape>(9); }},
      {"arena.queue = 9:", [](WorldParams& p) { p.queue = static_cast<QueueKind>(9); }},
      {"arena.influx = 9:", [](WorldParams& p) { p.influx = static_cast<InfluxKind>(9); }},
      {"arena.robot_radius = 0:", [](WorldParams& p) { p.robot_radius = 0; }},
      {"arena.robot_radius = nan:", [nan](WorldParams& p) { p.robot_radius = nan; }},
      {"model.delta = -0.1:", [](WorldParams& p) { p.delta = -0.1; }},
      {"model.delta = 0.05:", [](WorldParams& p) { p.delta = 0.05; }},  // < robot radius
      {"model.delta = 0.06:", [](WorldParams& p) { p.delta = 0.06; }},  // 2δ < D_s
      {"arena.safety_distance = 0.1:", [](WorldParams& p) { p.safety_distance = 0.1; }},  // < 2r
      {"model.v = 0:", [](WorldParams& p) { p.v = 0; }},
      {"model.v = 0.3:", [](WorldParams& p) { p.v = 0.3; }},  // > max_speed
      {"arena.max_speed = -1:", [](WorldParams& p) { p.max_speed = -1; }},
      {"arena.projection_distance = 0:", [](WorldParams& p) { p.projection_distance = 0; }},
      {"arena.projection_distance = 0.5:", [](WorldParams& p) { p.projection_distance = 0.5; }},
      {"arena.max_turn_rate = 2:", [](WorldParams& p) { p.max_turn_rate = 2; }},  // < v/l
      {"model.lambda_p = -1:", [](WorldParams& p) { p.lambda_p = -1; }},
      {"model.lambda_d = inf:",
       [](WorldParams& p) { p.lambda_d = std::numeric_limits<double>::infinity(); }},
      {"model.rho = 0:",
       [](WorldParams& p) {
         p.encounter_model = EncounterModel::kinetic;
         p.rho = 0;
       }},
      {"agent.dt = 0:", [](WorldParams& p) { p.tick_dt = 0; }},
      {"arena.physics_dt = -0.01:", [](WorldParams& p) { p.physics_dt = -0.01; }},
      {"arena.physics_dt = 0.04:", [](WorldParams& p) { p.physics_dt = 0.04; }},    // > tick_dt
      {"arena.physics_dt = 0.007:", [](WorldParams& p) { p.physics_dt = 0.007; }},  // no divisor
      {"arena.physics_dt = 0.2:",
       [](WorldParams& p) {
         p.physics_dt = 0.2;
         p.tick_dt = 0.2;
       }},  // 0.2·0.2 > δ/4
      {"arena.gamma = 0:", [](WorldParams& p) { p.gamma = 0; }},
      {"arena.boundary_gain = 200:", [](WorldParams& p) { p.boundary_gain = 200; }},  // > 1/dt
      {"arena.tumble_rate = -0.1:", [](WorldParams& p) { p.tumble_rate = -0.1; }},
      {"arena.unblock_time = 0:", [](WorldParams& p) { p.unblock_time = 0; }},
      {"agent.lambda_in = -0.02:", [](WorldParams& p) { p.lambda_in = -0.02; }},
      {"arena.missed_onsets = 1.5:", [](WorldParams& p) { p.missed_onsets = 1.5; }},
      {"arena.missed_onsets = -0.1:", [](WorldParams& p) { p.missed_onsets = -0.1; }},
      {"arena.false_onsets = -1:", [](WorldParams& p) { p.false_onsets = -1; }},
      {"arena.semi_axis_x = 0:", [](WorldParams& p) { p.semi_axis_x = 0; }},
      {"arena.semi_axis_y = 0.1:", [](WorldParams& p) { p.semi_axis_y = 0.1; }},  // too small
      {"arena.width = -3:",
       [](WorldParams& p) {
         p.shape = DomainShape::rectangle;
         p.width = -3;
       }},
      {"arena.height = 0.2:",
       [](WorldParams& p) {
         p.shape = DomainShape::rectangle;
         p.height = 0.2;
       }},
      {"arena.robots_inside = 500:", [](WorldParams& p) { p.robots_inside = 500; }},
      {"arena.robots_waiting = 400:", [](WorldParams& p) { p.robots_waiting = 400; }},
      {"arena.robots_waiting = 0:",
       [](WorldParams& p) {
         p.queue = QueueKind::endless;
         p.robots_waiting = 0;
       }},
      {"arena.robots_inside = 0:",
       [](WorldParams& p) {
         p.robots_inside = 0;
         p.robots_waiting = 0;
       }},
      // The limits on what a world allocates at its start and does in one tick.
      {"arena.semi_axis_x = 2000000:", [](WorldParams& p) { p.semi_axis_x = 2e6; }},
      {"arena.semi_axis_y = 1e+30:", [](WorldParams& p) { p.semi_axis_y = 1e30; }},
      {"arena.width = 1000001:",
       [](WorldParams& p) {
         p.shape = DomainShape::rectangle;
         p.width = 1000001;
       }},
      {"arena.height = 1e+200:",
       [](WorldParams& p) {
         p.shape = DomainShape::rectangle;
         p.height = 1e200;
       }},
      {"arena.physics_dt = 1e-09:", [](WorldParams& p) { p.physics_dt = 1e-9; }},  // 3·10⁷ steps a tick
      {"arena.robots_inside = 1000001:",
       [](WorldParams& p) {
         p.semi_axis_x = 1000;  // room for 1000001 robots
         p.semi_axis_y = 1000;
         p.lambda_p = 0;
         p.lambda_d = 0;
         p.robots_inside = 1000001;
       }},
      {"arena.robots_waiting = 999993:",
       [](WorldParams& p) {
         p.queue = QueueKind::endless;
         p.robots_waiting = 999993;  // with the 8 inside, one over
       }},
      {"arena.tumble_rate = 1000000000:", [](WorldParams& p) { p.tumble_rate = 1e9; }},  // 3·10⁷ a tick
      {"model.lambda_d = 1000000000000:",
       [](WorldParams& p) {
         p.encounter_model = EncounterModel::kinetic;  // 2δvλ_d·dt = 6·10⁸ drop-offs a tick
         p.lambda_d = 1e12;
       }},
      {"model.lambda_p = 1000000:", [](WorldParams& p) { p.lambda_p = 1e6; }},  // 3·10⁶ locations
      {"model.lambda_d = 1000:",
       [](WorldParams& p) {
         p.semi_axis_x = 1000;  // 3·10⁶ m²: 3·10⁹ locations
         p.semi_axis_y = 1000;
         p.lambda_p = 0;
         p.lambda_d = 1000;
       }},
  };
  for (const BadCase& c : cases) {
    WorldParams p;
    c.spoil(p);
    const std::string message = message_of(p);
    EXPECT_EQ(message.rfind(c.prefix, 0), 0u)
        << "expected '" << c.prefix << "...', got '" << message << "'";
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(PhysicsParams, MessagesStateTheAllowedRange) {
  WorldParams p;
  p.physics_dt = 0.007;
  EXPECT_NE(message_of(p).find("must divide agent.dt (0.03 s)"), std::string::npos)
      << message_of(p);
  p = WorldParams{};
  p.robots_inside = 500;
  EXPECT_NE(message_of(p).find("must be <= " + std::to_string(max_robots(p))), std::string::npos)
      << message_of(p);
}

TEST(PhysicsParams, TheLimitsAreInclusiveAndTheLocationLimitIsThePhysicalWorldsOwn) {
  WorldParams p;
  p.semi_axis_x = max_extent;
  p.semi_axis_y = max_extent;
  p.lambda_in = 0;  // no influx: the default's arrivals in this arena are refused on their own (below)
  p.lambda_p = max_task_locations / domain_of(p).area();  // exactly the most locations
  p.lambda_d = 0;
  EXPECT_NO_THROW(p.validate()) << message_of(p);
  p.lambda_p = 1.32;  // 4·10¹² locations: refused, with the density allowed in this arena
  EXPECT_EQ(message_of(p).rfind("model.lambda_p = 1.32: must be <= ", 0), 0u)
      << message_of(p);
  EXPECT_NE(message_of(p).find("at most 1000000 pick-up locations"), std::string::npos) << message_of(p);
  p.encounter_model = EncounterModel::kinetic;  // no locations: only their rates
  EXPECT_NO_THROW(p.validate()) << message_of(p);
  // The events a tick draws one by one: exactly the most is allowed.
  p = WorldParams{};
  p.tumble_rate = max_events_per_tick / p.tick_dt;
  EXPECT_NO_THROW(p.validate()) << message_of(p);
  p.tumble_rate = std::nextafter(p.tumble_rate, 1e300);
  EXPECT_EQ(message_of(p).rfind("arena.tumble_rate = ", 0), 0u) << message_of(p);
  EXPECT_NE(message_of(p).find("at most 1000 tumbles expected per robot per tick (agent.dt = 0.03 s)"),
            std::string::npos)
      << message_of(p);
  // The arrivals a tick draws one by one, either queue: exactly the most is allowed.
  for (const QueueKind queue : {QueueKind::finite, QueueKind::endless}) {
    p = WorldParams{};
    p.queue = queue;
    p.lambda_in = max_arrivals_per_tick / (domain_of(p).area() * p.tick_dt);
    EXPECT_NO_THROW(p.validate()) << message_of(p);
    p.lambda_in = std::nextafter(p.lambda_in, 1e300);
    EXPECT_EQ(message_of(p).rfind("agent.lambda_in = ", 0), 0u) << message_of(p);
    EXPECT_NE(message_of(p).find("at most 100000 arrivals expected per tick (agent.dt = 0.03 s)"), std::string::npos)
        << message_of(p);
  }
}

TEST(PhysicsParams, MaxRobotsSaturatesInAnArenaTooLargeToCount) {
  WorldParams p;
  p.semi_axis_x = max_extent;  // 3·10¹² m²: about 9·10¹³ safety discs
  p.semi_axis_y = max_extent;
  EXPECT_EQ(max_robots(p), std::numeric_limits<std::uint32_t>::max());
  p.semi_axis_x = 1000;  // 3.1·10⁶ m²: about 9.4·10⁷, counted
  p.semi_axis_y = 1000;
  EXPECT_GT(max_robots(p), 90'000'000u);
  EXPECT_LT(max_robots(p), 100'000'000u);
}

TEST(PhysicsParams, AnEndlessQueueDoesNotCountWaitingRobotsAgainstTheDomain) {
  WorldParams p;
  p.queue = QueueKind::endless;
  p.robots_waiting = 400;
  EXPECT_NO_THROW(p.validate());
}

TEST(PhysicsParams, MakeWorldValidatesFirst) {
  WorldParams p;
  p.tick_dt = -1;
  EXPECT_THROW(make_world(p), std::invalid_argument);
}

}  // namespace
}  // namespace retreat::physics
