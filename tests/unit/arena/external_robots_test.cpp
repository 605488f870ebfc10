// A mixed swarm's real robots in the physical world (arena.external_robots): posed from outside,
// never moved by the simulation, met and avoided by simulated robots, departing by their own
// motion or when lost.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "retreat/physics/world.hpp"

namespace retreat::physics {
namespace {

WorldParams mixed(std::uint32_t external) {
  WorldParams p;  // the Robotarium ellipse, 8 inside, 4 waiting
  p.robots_waiting = 0;
  p.external_robots = external;
  p.record_encounters = true;
  return p;
}

const RobotPose* pose_of(const Poses& poses, RobotId id) {
  for (const auto& r : poses.robots) {
    if (r.id == id) return &r;
  }
  return nullptr;
}

TEST(PhysicsExternalRobots, StayWhereTheirPoseIsSetWhileSimulatedRobotsMove) {
  auto world = make_world(mixed(1));
  ASSERT_TRUE(world->set_external_pose(0, 0.3, -0.2, 1.0));
  const auto before = world->poses();
  for (int k = 0; k < 100; ++k) world->step_tick();  // 3 s
  const auto after = world->poses();
  const auto* real = pose_of(after, 0);
  ASSERT_NE(real, nullptr);
  EXPECT_EQ(real->x, 0.3);
  EXPECT_EQ(real->y, -0.2);
  EXPECT_EQ(real->theta, 1.0);
  double moved = 0.0;
  for (RobotId id = 1; id < 8; ++id) {
    moved += std::hypot(pose_of(after, id)->x - pose_of(before, id)->x, pose_of(after, id)->y - pose_of(before, id)->y);
  }
  EXPECT_GT(moved, 7 * 0.1) << "the simulated robots walk (v = 0.1 m/s for 3 s)";
}

TEST(PhysicsExternalRobots, SimulatedRobotsMeetARealRobotAndBothCountTheOnset) {
  // A real robot sweeping through the middle of the ellipse meets simulated robots: onsets for
  // both, as between two simulated robots.
  auto world = make_world(mixed(1));
  std::uint64_t real_onsets = 0;
  for (int k = 0; k < 2000; ++k) {  // 60 s
    const double t = 0.03 * k;
    ASSERT_TRUE(world->set_external_pose(0, 0.8 * std::cos(0.25 * t), 0.5 * std::sin(0.25 * t), 0.25 * t));
    world->step_tick();
  }
  real_onsets = world->robot_stats(0).onsets;
  EXPECT_GT(real_onsets, 0u);
  std::uint64_t met_real = 0;
  for (const auto& c : world->take_contact_records()) {
    met_real += (c.robot == 0) != (c.other == 0) && c.other != no_robot ? 1 : 0;
  }
  EXPECT_GT(met_real, 0u) << "contact records between the real robot and simulated ones";
  // The simulated robots' barrier certificates keep them clear of it. Each certificate takes
  // half of a pair's avoidance and the real robot here takes none (it sweeps on regardless), so
  // only half of the safety distance D_s is owed to it: checked at the end of this fixed-seed run.
  const auto poses = world->poses();
  const auto* real = pose_of(poses, 0);
  for (const auto& r : poses.robots) {
    if (r.id != 0) {
      EXPECT_GT(std::hypot(r.x - real->x, r.y - real->y), 0.5 * world->params().safety_distance);
    }
  }
}

TEST(PhysicsExternalRobots, DepartsByItsOwnMotionOrWhenLostAndRefusesPosesThen) {
  auto world = make_world(mixed(2));
  // Robot 0 drives out of the ellipse (semi-axes 1.2 × 0.8) by itself, never told to retreat.
  ASSERT_TRUE(world->set_external_pose(0, 1.5, 0.0, 0.0));
  world->step_tick();
  EXPECT_EQ(world->robot_stats(0).phase, Phase::departed);
  EXPECT_FALSE(world->set_external_pose(0, 0.0, 0.0, 0.0)) << "a departed robot takes no pose";
  // Robot 1 is lost: it departs at once; its frame says so.
  EXPECT_TRUE(world->lose_external(1));
  EXPECT_EQ(world->robot_stats(1).phase, Phase::departed);
  EXPECT_FALSE(world->lose_external(1));
  world->step_tick();
  // Simulated robots are not real: neither call touches them.
  EXPECT_FALSE(world->set_external_pose(2, 0.0, 0.0, 0.0));
  EXPECT_FALSE(world->lose_external(2));
  EXPECT_FALSE(world->set_external_pose(7, std::nan(""), 0.0, 0.0));
  EXPECT_EQ(world->telemetry().inside, 6u);
}

TEST(PhysicsExternalRobots, TheParametersRefuseAKineticWorldAndMoreRealRobotsThanInside) {
  auto p = mixed(9);
  try {
    p.validate();
    FAIL() << "9 real robots of 8 inside accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("arena.external_robots = 9"), std::string::npos) << e.what();
  }
  p = mixed(1);
  p.encounter_model = EncounterModel::kinetic;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = mixed(1);
  p.external_lost_after = 0.1;  // below external_frozen_after (0.5)
  EXPECT_THROW(p.validate(), std::invalid_argument);
  // The kinetic world has no positions: it takes no pose.
  WorldParams kinetic;
  kinetic.encounter_model = EncounterModel::kinetic;
  auto world = make_world(kinetic);
  EXPECT_FALSE(world->set_external_pose(0, 0.0, 0.0, 0.0));
  EXPECT_FALSE(world->lose_external(0));
}

}  // namespace
}  // namespace retreat::physics
