#include "retreat/wire/topics.hpp"

#include <cctype>
#include <charconv>

namespace retreat::wire {
namespace {
std::string robot_topic(const std::string& prefix, RobotId robot, const char* leaf) {
  return prefix + "/robot_" + std::to_string(robot) + "/" + leaf;
}
}  // namespace

std::string proximity_topic(const std::string& prefix, RobotId robot) {
  return robot_topic(prefix, robot, "proximity");
}
std::string decision_topic(const std::string& prefix, RobotId robot) {
  return robot_topic(prefix, robot, "decision");
}
std::string plan_topic(const std::string& prefix, RobotId robot) { return robot_topic(prefix, robot, "plan"); }
std::string tracked_pose_topic(const std::string& prefix, RobotId robot) {
  return robot_topic(prefix, robot, "tracked_pose");
}
std::string agent_status_topic(const std::string& prefix) { return prefix + "/agent_status"; }
std::string arena_telemetry_topic(const std::string& prefix) { return prefix + "/arena_telemetry"; }
std::string poses_topic(const std::string& prefix) { return prefix + "/poses"; }

std::optional<RobotId> robot_of_topic(const std::string& topic) {
  const std::string marker = "/robot_";
  const auto at = topic.rfind(marker);
  if (at == std::string::npos) return std::nullopt;
  const char* first = topic.data() + at + marker.size();
  const char* last = topic.data() + topic.size();
  RobotId id = 0;
  const auto [end, error] = std::from_chars(first, last, id);
  if (error != std::errc() || end == first || end == last || *end != '/') return std::nullopt;
  return id;
}

bool is_valid_prefix(const std::string& prefix) {
  if (prefix.empty() || prefix.size() > 64 || prefix.front() == '/' || prefix.back() == '/') {
    return false;
  }
  char previous = '\0';
  for (const char c : prefix) {
    const bool word = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    if (!word && !(c == '/' && previous != '/')) return false;
    previous = c;
  }
  return true;
}

int robot_domain(int first_domain, int domains, RobotId robot) {
  return first_domain + static_cast<int>(robot % static_cast<RobotId>(domains));
}

}  // namespace retreat::wire
