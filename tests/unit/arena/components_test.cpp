// Encounter bookkeeping, the collection task, the influx and the walk's reflection rule.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "retreat/physics/collection_task.hpp"
#include "retreat/physics/encounter_tracker.hpp"
#include "retreat/physics/influx.hpp"
#include "retreat/physics/random_walk.hpp"

namespace retreat::physics {
namespace {

TEST(PhysicsEncounterTracker, CountsOneOnsetPerNewPartner) {
  EncounterTracker t(false);
  EXPECT_EQ(t.update(0, {3, 5}, 0.1), 2u);
  EXPECT_EQ(t.update(0, {3, 5}, 0.2), 0u);  // still in contact: no new onset
  EXPECT_EQ(t.update(0, {3, 5, 7}, 0.3), 1u);
  EXPECT_EQ(t.update(0, {7}, 0.4), 0u);  // partners leaving are not onsets
  EXPECT_TRUE(t.in_contact(0));
  EXPECT_EQ(t.update(0, {}, 0.5), 0u);
  EXPECT_FALSE(t.in_contact(0));
}

TEST(PhysicsEncounterTracker, APairThatSeparatesAndClosesAgainIsANewOnset) {
  EncounterTracker t(false);
  EXPECT_EQ(t.update(1, {2}, 0.1), 1u);
  EXPECT_EQ(t.update(1, {}, 0.2), 0u);
  EXPECT_EQ(t.update(1, {2}, 0.3), 1u);
}

TEST(PhysicsEncounterTracker, ContactsPresentAtTheStartAreNotOnsets) {
  EncounterTracker t(true);
  t.initialize(0, {1});
  t.initialize(1, {0});
  EXPECT_EQ(t.update(0, {1}, 0.1), 0u);
  EXPECT_EQ(t.update(0, {}, 0.2), 0u);
  EXPECT_TRUE(t.take_records().empty());  // its onset was never observed
}

TEST(PhysicsEncounterTracker, RecordsPairIntervalsOnceAndRobotEpisodes) {
  EncounterTracker t(true);
  // Robots 0 and 1 meet at 1.0; 0 and 2 meet at 1.5; all separate at 2.0.
  t.update(0, {1}, 1.0);
  t.update(1, {0}, 1.0);
  t.update(0, {1, 2}, 1.5);
  t.update(2, {0}, 1.5);
  t.update(0, {}, 2.0);
  t.update(1, {}, 2.0);
  t.update(2, {}, 2.0);
  const std::vector<ContactRecord> r = t.take_records();
  int pairs = 0;
  int episodes = 0;
  for (const ContactRecord& c : r) {
    if (c.other == no_robot) {
      ++episodes;
      EXPECT_DOUBLE_EQ(c.end, 2.0);
      EXPECT_DOUBLE_EQ(c.start, c.robot == 2 ? 1.5 : 1.0);
    } else {
      ++pairs;
      EXPECT_EQ(c.robot, 0u);
      EXPECT_DOUBLE_EQ(c.start, c.other == 1 ? 1.0 : 1.5);
    }
  }
  EXPECT_EQ(pairs, 2);
  EXPECT_EQ(episodes, 3);
  EXPECT_TRUE(t.take_records().empty());
}

TEST(PhysicsCollectionTask, HoldsTheRoundedMeanNumberOfLocations) {
  Rng rng(1);
  const Domain d = Domain::rectangle(10.0, 10.0);
  const CollectionTask task(d, 0.82, 0.66, 0.11, rng);
  EXPECT_EQ(task.pickups().size(), 82u);
  EXPECT_EQ(task.dropoffs().size(), 66u);
  for (const Vec2& p : task.pickups()) {
    EXPECT_TRUE(d.contains(p));
  }
}

TEST(PhysicsCollectionTask, AUsedPickUpLocationIsReplacedAndDropOffsPersist) {
  Rng rng(2);
  const Domain d = Domain::rectangle(10.0, 10.0);
  CollectionTask task(d, 0.82, 0.66, 0.11, rng);
  const Vec2 target = task.pickups()[10];
  EXPECT_TRUE(task.try_pick_up(target + Vec2(0.05, 0.05), rng));  // 7 cm away: within δ
  EXPECT_EQ(task.pickups().size(), 82u);
  EXPECT_NE(task.pickups()[10], target);
  const Vec2 depot = task.dropoffs()[3];
  EXPECT_TRUE(task.can_drop_off(depot + Vec2(0.1, 0.0)));
  EXPECT_TRUE(task.can_drop_off(depot + Vec2(0.1, 0.0)));
  EXPECT_EQ(task.dropoffs()[3], depot);
}

TEST(PhysicsCollectionTask, NothingHappensFartherThanDeltaFromEveryLocation) {
  Rng rng(3);
  const Domain d = Domain::rectangle(10.0, 10.0);
  CollectionTask task(d, 0.82, 0.66, 0.11, rng);
  for (int k = 0; k < 2000; ++k) {
    const Vec2 p = d.sample_uniform(rng);
    double nearest_pickup = 1e9;
    for (const Vec2& q : task.pickups()) {
      nearest_pickup = std::min(nearest_pickup, (q - p).norm());
    }
    double nearest_dropoff = 1e9;
    for (const Vec2& q : task.dropoffs()) {
      nearest_dropoff = std::min(nearest_dropoff, (q - p).norm());
    }
    EXPECT_EQ(task.can_drop_off(p), nearest_dropoff <= 0.11);
    EXPECT_EQ(task.try_pick_up(p, rng), nearest_pickup <= 0.11);
  }
}

TEST(PhysicsCollectionTask, APickUpTakesTheNearestLocationWithinDeltaWhateverTheSetsSize) {
  // 8 locations (looked up one by one) and 8,200 (looked up by cells): the location taken is
  // the nearest within δ, the lower index on a tie, as a search of every location finds it.
  for (const auto& [side, density] : {std::pair{2.0, 2.0}, std::pair{100.0, 0.82}}) {
    Rng rng(5);
    const Domain d = Domain::rectangle(side, side);
    CollectionTask task(d, density, density, 0.3, rng);
    ASSERT_EQ(task.pickups().size(), static_cast<std::size_t>(std::llround(density * side * side)));
    int taken = 0;
    for (int k = 0; k < 4000; ++k) {
      const Vec2 p = k % 2 == 0 ? d.sample_uniform(rng) : task.pickups()[static_cast<std::size_t>(k) % task.pickups().size()] + Vec2(0.2, -0.1);
      long nearest = -1;
      double nearest_d2 = 0.0;
      for (std::size_t i = 0; i < task.pickups().size(); ++i) {
        const double d2 = (task.pickups()[i] - p).squaredNorm();
        if (d2 <= 0.3 * 0.3 && (nearest < 0 || d2 < nearest_d2)) {
          nearest = static_cast<long>(i);
          nearest_d2 = d2;
        }
      }
      const std::vector<Vec2> before = task.pickups();
      ASSERT_EQ(task.try_pick_up(p, rng), nearest >= 0) << "side " << side << ", query " << k;
      for (std::size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(task.pickups()[i] != before[i], static_cast<long>(i) == nearest) << "side " << side << ", query " << k;
      }
      taken += nearest >= 0 ? 1 : 0;
    }
    EXPECT_GT(taken, 1000) << "side " << side;  // the queries beside a location find one
  }
}

TEST(PhysicsCollectionTask, AnArenaAsLargeAsAllowedWithoutLocationsIndexesNothing) {
  // No location: the index's cells had the 1 m side of an empty set, 4·10¹² of them (bad_alloc).
  // It now has at most 64, whatever the arena.
  Rng rng(3);
  const Domain d = Domain::rectangle(2e6, 2e6);
  CollectionTask task(d, 0.0, 0.0, 0.1, rng);
  EXPECT_TRUE(task.pickups().empty());
  EXPECT_TRUE(task.dropoffs().empty());
  for (const Vec2& p : {Vec2(0.0, 0.0), Vec2(-9.9e5, 9.9e5), Vec2(1e6, -1e6)}) {
    EXPECT_FALSE(task.try_pick_up(p, rng));
    EXPECT_FALSE(task.can_drop_off(p));
  }
}

TEST(PhysicsInflux, SteadyArrivalsComeEveryInverseRateSeconds) {
  Rng rng(4);
  Influx influx(InfluxKind::steady, 0.0603, rng);
  EXPECT_NEAR(influx.next_arrival(), 1.0 / 0.0603, 1e-12);
  EXPECT_EQ(influx.arrivals_until(16.0, rng), 0u);
  EXPECT_EQ(influx.arrivals_until(16.7, rng), 1u);
  EXPECT_EQ(influx.arrivals_until(100.0, rng), 5u);  // arrivals at 33.2, 49.8, 66.3, 82.9, 99.5
}

TEST(PhysicsInflux, PoissonArrivalsHaveTheRightMeanCount) {
  // Poisson(2000) count: sd 44.7; tolerance 5 sd (false failure ≈ 6e-7).
  Rng rng(5);
  Influx influx(InfluxKind::poisson, 2.0, rng);
  EXPECT_NEAR(static_cast<double>(influx.arrivals_until(1000.0, rng)), 2000.0, 224.0);
}

TEST(PhysicsInflux, ZeroRateMeansNoArrivals) {
  Rng rng(6);
  Influx influx(InfluxKind::steady, 0.0, rng);
  EXPECT_EQ(influx.arrivals_until(1e9, rng), 0u);
}

TEST(PhysicsRandomWalk, ReflectsOnlyWhenMovingOutwards) {
  Rng rng(7);
  WalkState w = start_walk(Vec2(1.0, 1.0), 0.0, 0.1, rng);
  EXPECT_FALSE(reflect_if_outward(w, Vec2(-1.0, 0.0)));
  EXPECT_TRUE(reflect_if_outward(w, Vec2(1.0, 0.0)));
  EXPECT_NEAR((w.direction - Vec2(-1.0, 1.0).normalized()).norm(), 0.0, 1e-15);
}

TEST(PhysicsRandomWalk, TumblesAtTheScheduledTimes) {
  Rng rng(8);
  WalkState w = start_walk(Vec2(1.0, 0.0), 0.0, 0.5, rng);
  const double first = w.next_tumble;
  EXPECT_FALSE(apply_tumbles(w, first - 1e-9, 0.5, rng));
  EXPECT_TRUE(apply_tumbles(w, first, 0.5, rng));
  EXPECT_GT(w.next_tumble, first);
}

TEST(PhysicsRandomWalk, AStalledWalkerReorientsAfterTheUnblockTime) {
  Rng rng(9);
  WalkState w = start_walk(Vec2(1.0, 0.0), 0.0, 0.0, rng);
  EXPECT_FALSE(unblock_if_stalled(w, Vec2(0.01, 0.0), 0.1, 1.0, 2.0, rng));  // stall begins
  EXPECT_FALSE(unblock_if_stalled(w, Vec2(0.01, 0.0), 0.1, 2.9, 2.0, rng));
  EXPECT_TRUE(unblock_if_stalled(w, Vec2(0.01, 0.0), 0.1, 3.0, 2.0, rng));
  EXPECT_DOUBLE_EQ(w.blocked_since, -1.0);
  w = start_walk(Vec2(1.0, 0.0), 0.0, 0.0, rng);
  EXPECT_FALSE(unblock_if_stalled(w, Vec2(0.01, 0.0), 0.1, 1.0, 2.0, rng));
  EXPECT_FALSE(unblock_if_stalled(w, Vec2(0.08, 0.0), 0.1, 2.0, 2.0, rng));  // progress resets
  EXPECT_FALSE(unblock_if_stalled(w, Vec2(0.01, 0.0), 0.1, 3.5, 2.0, rng));
}

TEST(PhysicsRetreatDetour, AStalledRetreatTurnsAfterTheUnblockTimeAndProgressResetsTheStall) {
  Rng rng(11);
  const Vec2 normal(0.6, 0.8);
  RetreatDetour d;
  EXPECT_EQ(retreat_direction(d, normal), normal);  // no detour: along the normal
  EXPECT_FALSE(detour_if_stalled(d, Vec2(0.0, 0.0), normal, 0.1, 1.0, 2.0, rng));  // stall begins
  EXPECT_FALSE(detour_if_stalled(d, Vec2(0.0, 0.0), normal, 0.1, 2.9, 2.0, rng));
  EXPECT_FALSE(d.active);
  EXPECT_TRUE(detour_if_stalled(d, Vec2(0.0, 0.0), normal, 0.1, 3.0, 2.0, rng));
  EXPECT_TRUE(d.active);
  EXPECT_DOUBLE_EQ(d.blocked_since, -1.0);
  EXPECT_NEAR(d.direction.norm(), 1.0, 1e-12);
  EXPECT_GE(d.direction.dot(normal), 0.0);
  EXPECT_EQ(retreat_direction(d, normal), d.direction);
  // Progress is measured along the detour now: v/2 along it keeps it going.
  EXPECT_FALSE(detour_if_stalled(d, 0.05 * d.direction, normal, 0.1, 4.0, 2.0, rng));
  EXPECT_DOUBLE_EQ(d.blocked_since, -1.0);
  // v/2 along the normal is not progress on a detour 80° away from it (0.05·cos 80° < 0.05).
  const double turned = std::atan2(normal.y(), normal.x()) + 80.0 * std::numbers::pi / 180.0;
  RetreatDetour sideways{true, Vec2(std::cos(turned), std::sin(turned)), -1.0};
  EXPECT_FALSE(detour_if_stalled(sideways, 0.05 * normal, normal, 0.1, 5.0, 2.0, rng));
  EXPECT_DOUBLE_EQ(sideways.blocked_since, 5.0);
}

// The detours are uniform within a quarter turn of the normal: never beyond it, on both sides.
// 4,000 draws from a fixed seed: each side holds 2,000 ± 32 (one sd), so 1,800 is six sd away; the
// draws within 22.5° of a quarter turn, a quarter of all, are 1,000 ± 27, so 850 is five sd away.
TEST(PhysicsRetreatDetour, DetoursAreUniformWithinAQuarterTurnOfTheNormal) {
  Rng rng(12);
  const Vec2 normal(-0.28, 0.96);
  int left = 0, right = 0, wide = 0;
  for (int k = 0; k < 4000; ++k) {
    RetreatDetour d;
    detour_if_stalled(d, Vec2::Zero(), normal, 0.1, 0.0, 2.0, rng);
    ASSERT_TRUE(detour_if_stalled(d, Vec2::Zero(), normal, 0.1, 2.0, 2.0, rng));
    const double along = d.direction.dot(normal);
    ASSERT_GE(along, -1e-12) << "beyond a quarter turn: " << d.direction.transpose();
    const double across = normal.x() * d.direction.y() - normal.y() * d.direction.x();
    (across > 0.0 ? left : right) += 1;
    if (along < std::cos(3.0 * std::numbers::pi / 8.0)) ++wide;
  }
  EXPECT_GT(left, 1800);
  EXPECT_GT(right, 1800);
  EXPECT_GT(wide, 850);
}

}  // namespace
}  // namespace retreat::physics
