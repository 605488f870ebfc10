#include "retreat/physics/unicycle.hpp"

#include <algorithm>
#include <cmath>

namespace retreat::physics {

UnicycleCommand clamp_command(const UnicycleCommand& command, double max_speed,
                              double max_turn_rate) {
  return {std::clamp(command.v, -max_speed, max_speed),
          std::clamp(command.omega, -max_turn_rate, max_turn_rate)};
}

double wrap_angle(double angle) {
  constexpr double pi = 3.14159265358979323846;
  if (angle > -pi && angle <= pi) {
    return angle;
  }
  double wrapped = std::remainder(angle, 2.0 * pi);  // in [−π, π]
  return wrapped <= -pi ? wrapped + 2.0 * pi : wrapped;
}

Pose integrate_euler(const Pose& pose, const UnicycleCommand& command, double dt) {
  return integrate_euler(pose, heading(pose.theta), command, dt);
}

Pose integrate_euler(const Pose& pose, const Vec2& e, const UnicycleCommand& command, double dt) {
  Pose next;
  next.position = pose.position + command.v * dt * e;
  next.theta = wrap_angle(pose.theta + command.omega * dt);
  return next;
}

}  // namespace retreat::physics
