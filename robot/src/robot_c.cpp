// The C API (retreat/robot/robot.h) over RobotLink. No exception crosses it.

#include <cstdio>
#include <exception>
#include <memory>
#include <stdexcept>

#include "retreat/robot/robot.h"
#include "retreat/robot/robot_link.hpp"
#include "retreat/scenario/scenario.hpp"

struct retreat_robot {
  std::unique_ptr<retreat::robot::RobotLink> link;
};

namespace {

using retreat::robot::LinkOptions;

void write_error(retreat_robot_error* error, int code, const char* message) {
  if (error == nullptr) return;
  error->code = code;
  std::snprintf(error->message, sizeof error->message, "%s", message);
}

std::chrono::nanoseconds seconds(double s) {
  if (!(s > 0.0)) return std::chrono::nanoseconds(0);  // negative and NaN: do not wait
  if (s > 1e9) s = 1e9;
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(s));
}

LinkOptions to_options(const retreat_robot_options& c) {
  if (c.scenario != nullptr) {
    return retreat::robot::link_options(retreat::scenario::load(c.scenario), c.robot_id);
  }
  LinkOptions options;
  options.robot_id = c.robot_id;
  if (c.vendor != nullptr) options.vendor = c.vendor;
  if (c.prefix != nullptr) options.prefix = c.prefix;
  options.participant.domain_id = c.domain;
  if (c.profile != nullptr) options.participant.profile = c.profile;
  options.lockstep = c.lockstep != 0;
  options.tracked = c.tracked != 0;
  return options;
}

}  // namespace

extern "C" {

void retreat_robot_options_init(retreat_robot_options* options) {
  if (options == nullptr) return;
  *options = retreat_robot_options{0, nullptr, "cyclonedds", 0, "retreat", nullptr, 0, 0};
}

retreat_robot* retreat_robot_join(const retreat_robot_options* options, retreat_robot_error* error) {
  write_error(error, RETREAT_ROBOT_OK, "");
  if (options == nullptr) {
    write_error(error, RETREAT_ROBOT_BAD_OPTIONS, "retreat_robot_join: options is NULL");
    return nullptr;
  }
  try {
    auto robot = std::make_unique<retreat_robot>();
    robot->link = std::make_unique<retreat::robot::RobotLink>(to_options(*options));
    return robot.release();
  } catch (const std::invalid_argument& e) {
    write_error(error, RETREAT_ROBOT_BAD_OPTIONS, e.what());
  } catch (const std::exception& e) {
    write_error(error, RETREAT_ROBOT_MIDDLEWARE, e.what());
  }
  return nullptr;
}

int retreat_robot_wait_for_agent(retreat_robot* robot, double timeout_s) {
  return robot != nullptr && robot->link->wait_for_agent(seconds(timeout_s)) ? 1 : 0;
}

int64_t retreat_robot_report(retreat_robot* robot, double time, uint8_t phase, int in_contact,
                             uint32_t new_onsets) {
  if (robot == nullptr) return -1;
  try {
    const auto tick = robot->link->report(time, static_cast<retreat::wire::Phase>(phase), in_contact != 0, new_onsets);
    return tick ? *tick : -1;
  } catch (const std::exception&) {
    return -1;  // the middleware failed
  }
}

int64_t retreat_robot_report_pose(retreat_robot* robot, double time, double x, double y, double theta) {
  if (robot == nullptr) return -1;
  try {
    const auto seq = robot->link->report_pose(time, x, y, theta);
    return seq ? *seq : -1;
  } catch (const std::exception&) {
    return -1;  // the middleware failed
  }
}

int retreat_robot_tracked(const retreat_robot* robot) {
  return robot != nullptr && robot->link->options().tracked ? 1 : 0;
}

int retreat_robot_poll(retreat_robot* robot) {
  try {
    return robot != nullptr && robot->link->poll() ? 1 : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

int retreat_robot_await_answer(retreat_robot* robot, double timeout_s) {
  try {
    return robot != nullptr && robot->link->await_answer(seconds(timeout_s)) ? 1 : 0;
  } catch (const std::exception&) {
    return 0;
  }
}

int retreat_robot_retreat(const retreat_robot* robot) {
  return robot != nullptr && robot->link->retreat() ? 1 : 0;
}

int retreat_robot_lockstep(const retreat_robot* robot) {
  return robot != nullptr && robot->link->options().lockstep ? 1 : 0;
}

double retreat_robot_now(const retreat_robot* robot) { return robot != nullptr ? robot->link->now() : 0.0; }

void retreat_robot_get_counters(const retreat_robot* robot, retreat_robot_counters* counters) {
  if (counters == nullptr) return;
  *counters = retreat_robot_counters{};
  if (robot == nullptr) return;
  const auto c = robot->link->counters();
  *counters = {c.frames_sent,        c.frames_resent,    c.reports_refused, c.write_failures,
               c.decisions_accepted, c.decisions_future, c.decisions_stale, c.decisions_invalid};
}

const char* retreat_robot_refused_reason(const retreat_robot* robot) {
  return robot != nullptr ? robot->link->refused_reason().c_str() : "";
}

void retreat_robot_leave(retreat_robot* robot) { delete robot; }

}  // extern "C"
