#include "retreat/recorder/scene.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

namespace retreat::recorder {
namespace {

using nlohmann::json;

json color(double r, double g, double b, double a = 1.0) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }

json pose(double x, double y, double z, double yaw = 0.0) {
  // A rotation by yaw about z as a quaternion.
  return {{"position", {{"x", x}, {"y", y}, {"z", z}}},
          {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(yaw / 2)}, {"w", std::cos(yaw / 2)}}}};
}

json entity(const std::string& id, std::uint64_t time_ns) {
  return {{"timestamp", {{"sec", time_ns / 1'000'000'000}, {"nsec", time_ns % 1'000'000'000}}},
          {"frame_id", std::string(scene_frame)},
          {"id", id},
          {"lifetime", {{"sec", 0}, {"nsec", 0}}},  // until replaced
          {"frame_locked", false},
          {"metadata", json::array()},
          {"arrows", json::array()},
          {"cubes", json::array()},
          {"spheres", json::array()},
          {"cylinders", json::array()},
          {"lines", json::array()},
          {"triangles", json::array()},
          {"texts", json::array()},
          {"models", json::array()}};
}

json phase_color(wire::Phase phase) {
  switch (phase) {
    case wire::Phase::waiting: return color(0.6, 0.6, 0.6);
    case wire::Phase::inside: return color(0.2, 0.5, 0.9);
    case wire::Phase::retreating: return color(1.0, 0.6, 0.1);
    case wire::Phase::departed: return color(0.6, 0.6, 0.6, 0.25);
  }
  return color(1, 0, 1);
}

/// The domain's outline: a closed loop of points (64 for the ellipse).
json outline(const physics::WorldParams& world, std::uint64_t time_ns) {
  auto e = entity("domain", time_ns);
  json points = json::array();
  if (world.shape == physics::DomainShape::ellipse) {
    constexpr int n = 64;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      points.push_back({{"x", world.semi_axis_x * std::cos(a)}, {"y", world.semi_axis_y * std::sin(a)}, {"z", 0.0}});
    }
  } else {
    const double x = world.width / 2, y = world.height / 2;
    for (const auto& [px, py] : {std::pair{-x, -y}, {x, -y}, {x, y}, {-x, y}}) {
      points.push_back({{"x", px}, {"y", py}, {"z", 0.0}});
    }
  }
  e["lines"].push_back({{"type", 1},  // LINE_LOOP
                        {"pose", pose(0, 0, 0)},
                        {"thickness", 0.01},
                        {"scale_invariant", false},
                        {"points", points},
                        {"color", color(0.1, 0.1, 0.1)},
                        {"colors", json::array()},
                        {"indices", json::array()}});
  return e;
}

}  // namespace

std::string scene_update_json(const wire::Poses& poses, const physics::WorldParams& world, std::uint64_t time_ns) {
  const double r = world.robot_radius;
  auto robots = entity("robots", time_ns);
  robots["metadata"].push_back({{"key", "tick"}, {"value", std::to_string(poses.tick)}});
  robots["metadata"].push_back({{"key", "time"}, {"value", std::to_string(poses.time)}});
  for (const auto& p : poses.robots) {
    robots["cylinders"].push_back({{"pose", pose(p.x, p.y, r / 2)},
                                   {"size", {{"x", 2 * r}, {"y", 2 * r}, {"z", r}}},
                                   {"bottom_scale", 1.0},
                                   {"top_scale", 1.0},
                                   {"color", phase_color(p.phase)}});
    robots["arrows"].push_back({{"pose", pose(p.x, p.y, r * 1.1, p.theta)},
                                {"shaft_length", r},
                                {"shaft_diameter", r / 5},
                                {"head_length", r / 2},
                                {"head_diameter", r / 2.5},
                                {"color", p.loaded ? color(0.1, 0.7, 0.2) : color(1, 1, 1)}});
    robots["texts"].push_back({{"pose", pose(p.x, p.y, 2.5 * r)},
                               {"billboard", true},
                               {"font_size", 12.0},
                               {"scale_invariant", true},
                               {"color", color(0, 0, 0)},
                               {"text", std::to_string(p.robot_id)}});
  }
  auto objects = entity("objects", time_ns);
  const double d = world.delta;
  for (const auto& p : poses.pickups) {
    objects["spheres"].push_back({{"pose", pose(p.x, p.y, 0)}, {"size", {{"x", d}, {"y", d}, {"z", d}}}, {"color", color(0.1, 0.7, 0.2, 0.8)}});
  }
  for (const auto& p : poses.dropoffs) {
    objects["spheres"].push_back({{"pose", pose(p.x, p.y, 0)}, {"size", {{"x", d}, {"y", d}, {"z", d}}}, {"color", color(0.1, 0.3, 0.9, 0.8)}});
  }
  const json update = {{"deletions", json::array()}, {"entities", {outline(world, time_ns), robots, objects}}};
  return update.dump();
}

}  // namespace retreat::recorder
