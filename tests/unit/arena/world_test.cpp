// Both worlds: queue and influx, retreat, commands, frames and determinism.

#include "retreat/physics/world.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace retreat::physics {
namespace {

class PhysicsWorld : public ::testing::TestWithParam<std::string> {
 protected:
  /// The Robotarium experiment: 8 robots inside, 4 waiting, λ_in·|D| = 0.0603 robots/s.
  WorldParams robotarium() const {
    WorldParams p;
    p.encounter_model = *value_of<EncounterModel>(GetParam());
    return p;
  }
  /// The same arena with an endless queue: 2 always waiting, λ_in·|D| = 0.3 robots/s.
  WorldParams endless() const {
    WorldParams p = robotarium();
    p.queue = QueueKind::endless;
    p.robots_waiting = 2;
    p.lambda_in = 0.1;
    return p;
  }
  static void run_for(World& world, double seconds) {
    const double dt = world.params().tick_dt;
    for (long k = 0; k < std::lround(seconds / dt); ++k) {
      world.step_tick();
    }
  }
};

TEST_P(PhysicsWorld, StartsWithTheConfiguredRobotsInsideAndWaiting) {
  auto world = make_world(robotarium());
  const Telemetry t = world->telemetry();
  EXPECT_EQ(t.tick, 0);
  EXPECT_EQ(t.inside, 8u);
  EXPECT_EQ(t.waiting, 4u);
  EXPECT_EQ(world->robot_count(), 12u);
  ASSERT_EQ(world->frames().size(), 12u);
  for (const RobotFrame& f : world->frames()) {
    EXPECT_EQ(f.phase, f.id < 8 ? Phase::inside : Phase::waiting);
    EXPECT_EQ(f.tick, 0);
  }
  EXPECT_NEAR(t.true_density, 8.0 / (3.14159265358979323846 * 1.2 * 0.8), 1e-12);
  for (RobotId id = 0; id < 12; ++id) {  // agents.csv tells the two apart by entered_at
    EXPECT_EQ(world->robot_stats(id).entered_at, id < 8 ? 0.0 : -1.0) << "robot " << id;
  }
}

TEST_P(PhysicsWorld, AFiniteQueueEmptiesAtTheInfluxRate) {
  auto world = make_world(robotarium());
  const double rate = 0.02 * 3.14159265358979323846 * 1.2 * 0.8;  // 0.0603 robots/s
  run_for(*world, 80.0);
  for (RobotId id = 8; id < 12; ++id) {
    const double due = (id - 7) / rate;  // 16.6, 33.2, 49.8, 66.3 s
    // Entry happens at the first step (physical) or tick end (kinetic) at or after the arrival;
    // the physical world may wait for room near the boundary, which at 8 robots in 3 m² takes
    // at most a few steps.
    EXPECT_GE(world->robot_stats(id).entered_at, due - 1e-9) << "robot " << id;
    EXPECT_LE(world->robot_stats(id).entered_at, due + 0.5) << "robot " << id;
  }
  const Telemetry t = world->telemetry();
  EXPECT_EQ(t.waiting, 0u);
  EXPECT_EQ(t.inside, 12u);
  EXPECT_EQ(world->robot_count(), 12u);  // a finite queue creates no robots
}

TEST_P(PhysicsWorld, AnEndlessQueueCreatesANewRobotForEachEntry) {
  auto world = make_world(endless());
  run_for(*world, 10.1);  // arrivals at 3.3, 6.6, 9.9 s
  const Telemetry t = world->telemetry();
  EXPECT_EQ(t.waiting, 2u);
  EXPECT_EQ(t.inside, 11u);
  EXPECT_EQ(world->robot_count(), 13u);  // ids 10, 11, 12 were created
  EXPECT_EQ(world->robot_stats(12).phase, Phase::waiting);
  EXPECT_EQ(world->robot_stats(8).phase, Phase::inside);
}

TEST_P(PhysicsWorld, TelemetrySumsEveryRobotInIdOrderWhileRobotsDepartInAnyOrder) {
  // telemetry() resumes its sums after the robots that have departed (their stats never change):
  // the result must be the sum over every robot in id order, bit for bit, whichever order they
  // leave in. Robots are sent out in an order that is not their ids' (newest first, then oldest).
  auto world = make_world(endless());
  std::size_t departed_seen = 0;
  for (long k = 0; k < 4000; ++k) {
    if (k % 150 == 75) {
      const auto n = static_cast<RobotId>(world->robot_count());
      for (RobotId i = 0; i < n; ++i) {  // the newest inside on odd rounds, the oldest on even
        const RobotId id = (k / 150) % 2 == 1 ? n - 1 - i : i;
        if (world->robot_stats(id).phase == Phase::inside) {
          world->command_retreat(id);
          break;
        }
      }
    }
    world->step_tick();
    const Telemetry t = world->telemetry();
    std::array<double, task_state_count> time{};
    std::uint32_t departed = 0;
    for (RobotId id = 0; id < world->robot_count(); ++id) {
      const RobotStats& s = world->robot_stats(id);
      departed += s.phase == Phase::departed ? 1 : 0;
      for (std::size_t j = 0; j < task_state_count; ++j) time[j] += s.state_time[j];
    }
    ASSERT_EQ(t.departed, departed) << "tick " << k;
    for (std::size_t j = 0; j < task_state_count; ++j) ASSERT_EQ(t.state_time[j], time[j]) << "tick " << k << ", state " << j;
    departed_seen = departed;
  }
  EXPECT_GE(departed_seen, 10u);  // the cache was used: many robots left, not in id order
}

TEST_P(PhysicsWorld, ACommandedRobotRetreatsAndDepartsOnce) {
  auto world = make_world(robotarium());
  EXPECT_EQ(world->command_retreat(3), CommandVerdict::accepted);
  EXPECT_EQ(world->robot_stats(3).phase, Phase::retreating);
  int departed_frames = 0;
  double departed_frame_time = -1.0;
  bool seen_retreating = false;
  for (long k = 0; k < std::lround(40.0 / world->params().tick_dt); ++k) {
    world->step_tick();
    for (const RobotFrame& f : world->frames()) {
      if (f.id != 3) {
        continue;
      }
      seen_retreating = seen_retreating || f.phase == Phase::retreating;
      if (f.phase == Phase::departed) {
        ++departed_frames;
        departed_frame_time = f.time;
      }
    }
  }
  EXPECT_TRUE(seen_retreating);
  EXPECT_EQ(departed_frames, 1);
  const RobotStats& st = world->robot_stats(3);
  EXPECT_EQ(st.phase, Phase::departed);
  // The farthest point of the 1.2 × 0.8 ellipse is 0.8 m from its boundary: 8 s at 0.1 m/s;
  // avoidance may add a little.
  EXPECT_GT(st.departed_at, 0.0);
  EXPECT_LT(st.departed_at, 20.0);
  // Its one departed frame is the frame of the tick in which it left.
  EXPECT_GE(departed_frame_time, st.departed_at - 1e-9);
  EXPECT_LT(departed_frame_time - world->params().tick_dt, st.departed_at);
  const Telemetry t = world->telemetry();
  EXPECT_EQ(t.departed, 1u);
  EXPECT_EQ(t.inside + t.waiting + t.retreating, 11u);
}

// telemetry() is computed once per tick and kept: a command between two steps must show in it at
// once, and a step must replace it.
TEST_P(PhysicsWorld, TelemetryFollowsACommandAndAStepWithinTheTick) {
  auto world = make_world(robotarium());
  world->step_tick();
  const Telemetry before = world->telemetry();
  ASSERT_EQ(before.retreating, 0u);
  ASSERT_EQ(world->command_retreat(2), CommandVerdict::accepted);
  const Telemetry commanded = world->telemetry();
  EXPECT_EQ(commanded.tick, before.tick);
  EXPECT_EQ(commanded.retreating, 1u);
  EXPECT_EQ(commanded.inside, before.inside - 1);
  EXPECT_EQ(commanded.commands.accepted, 1u);
  EXPECT_EQ(world->command_retreat(2), CommandVerdict::already_retreating);
  EXPECT_EQ(world->telemetry().commands.already_retreating, 1u);
  world->step_tick();
  EXPECT_EQ(world->telemetry().tick, before.tick + 1);
  EXPECT_GT(world->telemetry().time, before.time);
}

TEST_P(PhysicsWorld, CommandsForUnknownWaitingOrDepartedRobotsAreRejectedAndCounted) {
  auto world = make_world(robotarium());
  EXPECT_EQ(world->command_retreat(999), CommandVerdict::unknown_robot);
  EXPECT_EQ(world->command_retreat(10), CommandVerdict::not_inside);  // waiting
  EXPECT_EQ(world->command_retreat(0), CommandVerdict::accepted);
  EXPECT_EQ(world->command_retreat(0), CommandVerdict::already_retreating);
  run_for(*world, 20.0);
  ASSERT_EQ(world->robot_stats(0).phase, Phase::departed);
  EXPECT_EQ(world->command_retreat(0), CommandVerdict::not_inside);
  const CommandCounts c = world->telemetry().commands;
  EXPECT_EQ(c.accepted, 1u);
  EXPECT_EQ(c.already_retreating, 1u);
  EXPECT_EQ(c.rejected_not_inside, 2u);
  EXPECT_EQ(c.rejected_unknown, 1u);
  EXPECT_THROW(world->robot_stats(999), std::out_of_range);
}

TEST_P(PhysicsWorld, FramesCarryEveryOnsetExactlyOnce) {
  WorldParams p = robotarium();
  p.robots_inside = 30;
  p.robots_waiting = 0;
  auto world = make_world(p);
  std::uint64_t from_frames = 0;
  for (int k = 0; k < 2000; ++k) {
    world->step_tick();
    for (const RobotFrame& f : world->frames()) {
      EXPECT_EQ(f.tick, k + 1);
      EXPECT_NEAR(f.time, (k + 1) * p.tick_dt, 1e-9);
      from_frames += f.new_onsets;
    }
  }
  EXPECT_GT(from_frames, 0u);
  EXPECT_EQ(from_frames, world->telemetry().onsets);
}

TEST_P(PhysicsWorld, TheSameSeedGivesTheSameRunAndAnotherSeedAnotherRun) {
  WorldParams p = robotarium();
  p.robots_inside = 20;
  const auto trace = [&](std::uint64_t seed) {
    WorldParams q = p;
    q.seed = seed;
    auto world = make_world(q);
    std::vector<double> out;
    for (int k = 0; k < 3000; ++k) {
      world->step_tick();
      if (k % 100 == 0) {
        world->command_retreat(static_cast<RobotId>(k / 100));
      }
      for (const RobotFrame& f : world->frames()) {
        out.push_back(f.new_onsets + 10.0 * static_cast<int>(f.phase));
      }
      for (const RobotPose& r : world->poses().robots) {
        out.push_back(r.x);
        out.push_back(r.theta);
      }
    }
    const Telemetry t = world->telemetry();
    out.push_back(static_cast<double>(t.onsets));
    out.push_back(static_cast<double>(t.deliveries));
    return out;
  };
  EXPECT_EQ(trace(5), trace(5));
  EXPECT_NE(trace(5), trace(6));
}

INSTANTIATE_TEST_SUITE_P(BothEncounterModels, PhysicsWorld,
                         ::testing::Values("physical", "kinetic"),
                         [](const ::testing::TestParamInfo<std::string>& model) {
                           return model.param;
                         });

TEST(PhysicsPhysicalWorld, RetreatingRobotsStillCauseEncountersUntilTheyLeave) {
  WorldParams p;
  p.robots_inside = 60;
  p.robots_waiting = 0;
  p.semi_axis_x = 1.6;
  p.semi_axis_y = 1.0;
  auto world = make_world(p);
  for (int k = 0; k < 300; ++k) {
    world->step_tick();
  }
  for (RobotId id = 0; id < 60; ++id) {
    world->command_retreat(id);
  }
  std::uint64_t retreating_onsets = 0;
  for (int k = 0; k < 1000; ++k) {
    world->step_tick();
    for (const RobotFrame& f : world->frames()) {
      retreating_onsets += f.phase == Phase::retreating ? f.new_onsets : 0;
    }
  }
  EXPECT_GT(retreating_onsets, 0u);
  EXPECT_EQ(world->telemetry().departed, 60u);
  EXPECT_TRUE(world->poses().robots.empty());
}

TEST(PhysicsPhysicalWorld, EnteringRobotsComeInThroughTheBoundary) {
  WorldParams p;
  p.robots_inside = 2;
  p.robots_waiting = 1;
  p.lambda_in = 0.2;  // arrival at 1.66 s
  p.tick_dt = p.physics_dt;
  auto world = make_world(p);
  bool seen_outside = false;
  for (int k = 0; k < 1000; ++k) {
    world->step_tick();
    for (const RobotPose& r : world->poses().robots) {
      if (r.id == 2 && r.entering) {
        const double g = std::pow(r.x / 1.2, 2) + std::pow(r.y / 0.8, 2);
        seen_outside = seen_outside || g > 1.0;
      }
    }
  }
  EXPECT_TRUE(seen_outside);  // its centre started outside D
  for (const RobotPose& r : world->poses().robots) {
    EXPECT_FALSE(r.entering);  // and it has finished entering
  }
}

}  // namespace
}  // namespace retreat::physics
