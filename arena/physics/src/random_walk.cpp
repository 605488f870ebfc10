#include "retreat/physics/random_walk.hpp"

#include <cmath>

namespace retreat::physics {

WalkState start_walk(const Vec2& direction, double now, double tumble_rate, Rng& rng) {
  WalkState walk;
  walk.direction = direction.normalized();
  walk.next_tumble = now + rng.exponential(tumble_rate);
  return walk;
}

bool apply_tumbles(WalkState& walk, double now, double tumble_rate, Rng& rng) {
  bool changed = false;
  while (walk.next_tumble <= now) {
    const double angle = rng.angle();
    walk.direction = Vec2(std::cos(angle), std::sin(angle));
    walk.next_tumble += rng.exponential(tumble_rate);
    changed = true;
  }
  return changed;
}

bool unblock_if_stalled(WalkState& walk, const Vec2& u, double speed, double now,
                        double unblock_time, Rng& rng) {
  if (u.dot(walk.direction) >= 0.5 * speed) {
    walk.blocked_since = -1.0;
    return false;
  }
  if (walk.blocked_since < 0.0) {
    walk.blocked_since = now;
    return false;
  }
  if (now - walk.blocked_since < unblock_time) {
    return false;
  }
  const double angle = rng.angle();
  walk.direction = Vec2(std::cos(angle), std::sin(angle));
  walk.blocked_since = -1.0;
  return true;
}

bool reflect_if_outward(WalkState& walk, const Vec2& outward_normal) {
  const double outward = walk.direction.dot(outward_normal);
  if (outward <= 0.0) {
    return false;
  }
  walk.direction -= 2.0 * outward * outward_normal;
  walk.direction.normalize();  // keeps |d| = 1 against rounding drift
  return true;
}

}  // namespace retreat::physics
