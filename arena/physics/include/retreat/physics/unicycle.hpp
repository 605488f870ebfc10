#pragma once
/// @file
/// Unicycle kinematics and the near-identity map to the point projected l ahead of the centre.
///
///   ẋ = v cosθ,  ẏ = v sinθ,  θ̇ = ω;     q = p + l·e(θ),  e(θ) = (cosθ, sinθ), n(θ) = (−sinθ,
///   cosθ) q̇ = v·e + lω·n, so a desired velocity u of q maps to v = eᵀu, ω = nᵀu / l (MODEL.md §6).

#include <cmath>

#include "retreat/physics/types.hpp"

namespace retreat::physics {

/// Pose of a unicycle: centre [m] and heading θ [rad] in (−π, π].
struct Pose {
  Vec2 position = Vec2::Zero();
  double theta = 0.0;
};

/// Unicycle input: linear speed v [m/s] (negative drives backwards), turn rate ω [rad/s].
struct UnicycleCommand {
  double v = 0.0;
  double omega = 0.0;
};

/// Unit heading e(θ).
inline Vec2 heading(double theta) { return {std::cos(theta), std::sin(theta)}; }

/// q = p + l·e(θ) [m].
inline Vec2 projected_point(const Pose& pose, double l) {
  return pose.position + l * heading(pose.theta);
}

/// (v, ω) = (eᵀu, nᵀu / l) for a desired velocity @p u of the projected point. Precondition: l > 0.
inline UnicycleCommand to_unicycle_command(const Vec2& e, const Vec2& u, double l) {
  return {e.x() * u.x() + e.y() * u.y(), (-e.y() * u.x() + e.x() * u.y()) / l};
}

/// The velocity of the projected point, v·e + lω·n [m/s].
inline Vec2 projected_velocity(const Vec2& e, const UnicycleCommand& command, double l) {
  return command.v * e + l * command.omega * Vec2(-e.y(), e.x());
}

/// @p command with v clamped to [−max_speed, max_speed] and ω to [−max_turn_rate, max_turn_rate].
UnicycleCommand clamp_command(const UnicycleCommand& command, double max_speed,
                              double max_turn_rate);

/// One forward-Euler step of length @p dt [s]: p += v·e(θ)·dt, θ += ω·dt (wrapped to (−π, π]).
Pose integrate_euler(const Pose& pose, const UnicycleCommand& command, double dt);

/// The same step with e = heading(pose.theta) given (a caller that has it already): the same
/// numbers, without computing the cosine and sine again.
Pose integrate_euler(const Pose& pose, const Vec2& e, const UnicycleCommand& command, double dt);

/// @p angle wrapped to (−π, π] [rad].
double wrap_angle(double angle);

}  // namespace retreat::physics
