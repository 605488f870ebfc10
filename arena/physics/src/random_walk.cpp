#include "retreat/physics/random_walk.hpp"

#include <cmath>
#include <numbers>

namespace retreat::physics {

namespace {

/// The stall clock of the unblock rules: @p blocked_since is when the current stall began (−1
/// while @p progressing). True once a stall has lasted @p unblock_time; the clock then restarts.
bool stall_over(double& blocked_since, bool progressing, double now, double unblock_time) {
  if (progressing) {
    blocked_since = -1.0;
    return false;
  }
  if (blocked_since < 0.0) {
    blocked_since = now;
    return false;
  }
  if (now - blocked_since < unblock_time) {
    return false;
  }
  blocked_since = -1.0;
  return true;
}

}  // namespace

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
  if (!stall_over(walk.blocked_since, u.dot(walk.direction) >= 0.5 * speed, now, unblock_time)) {
    return false;
  }
  const double angle = rng.angle();
  walk.direction = Vec2(std::cos(angle), std::sin(angle));
  return true;
}

bool detour_if_stalled(RetreatDetour& detour, const Vec2& u, const Vec2& outward_normal,
                       double speed, double now, double unblock_time, Rng& rng) {
  if (!stall_over(detour.blocked_since, u.dot(retreat_direction(detour, outward_normal)) >= 0.5 * speed, now,
                  unblock_time)) {
    return false;
  }
  const double angle = std::atan2(outward_normal.y(), outward_normal.x()) +
                       rng.uniform(-0.5 * std::numbers::pi, 0.5 * std::numbers::pi);
  detour.direction = Vec2(std::cos(angle), std::sin(angle));
  detour.active = true;
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
