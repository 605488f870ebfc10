#include "retreat/robot/endpoints.hpp"

#include "retreat/wire/topics.hpp"

namespace retreat::robot {

Endpoints::Endpoints(transport::Transport& transport, const std::string& prefix, wire::RobotId id)
    : frames(transport.create_writer<wire::ProximityFrame>(
          {wire::proximity_topic(prefix, id), transport::QosIntent::control()})),
      decisions(decision_reader(transport, prefix, id)) {}

transport::Reader<wire::Decision> decision_reader(transport::Transport& transport, const std::string& prefix,
                                                  wire::RobotId id) {
  return transport.create_reader<wire::Decision>({wire::decision_topic(prefix, id), transport::QosIntent::control()});
}

transport::Reader<wire::Decision> plan_reader(transport::Transport& transport, const std::string& prefix,
                                              wire::RobotId id) {
  return transport.create_reader<wire::Decision>({wire::plan_topic(prefix, id), transport::QosIntent::control()});
}

transport::Writer<wire::Poses> tracked_pose_writer(transport::Transport& transport, const std::string& prefix,
                                                   wire::RobotId id) {
  return transport.create_writer<wire::Poses>({wire::tracked_pose_topic(prefix, id), transport::QosIntent::control()});
}

transport::Reader<wire::Poses> tracked_pose_reader(transport::Transport& transport, const std::string& prefix,
                                                   wire::RobotId id) {
  return transport.create_reader<wire::Poses>({wire::tracked_pose_topic(prefix, id), transport::QosIntent::control()});
}

DecisionVerdict judge(const wire::Decision& d, std::int64_t current, bool lockstep) {
  if (d.tick > current) return DecisionVerdict::future;
  if (lockstep && d.tick < current) return DecisionVerdict::stale;
  return DecisionVerdict::accepted;
}

DecisionVerdict judge_plan(const wire::Decision& plan, std::int64_t tick, double time) {
  if (plan.time > time) return DecisionVerdict::future;
  if (plan.time < time || plan.tick < tick) return DecisionVerdict::stale;
  return DecisionVerdict::accepted;
}

}  // namespace retreat::robot
