#pragma once
// Plain <-> Cyclone DDS generated (C) types. Only this adapter sees the generated structs.

#include "retreat/wire/messages.hpp"
#include "retreat_msgs.h"

namespace retreat::transport::cyclonedds {

// to_vendor fills `out`, which stays valid only while `in` (and `scratch` for Poses) lives: the
// sequences point into the plain message's vectors, nothing is copied.
void to_vendor(const wire::ProximityFrame& in, retreat_msg_ProximityFrame& out);
void to_vendor(const wire::Decision& in, retreat_msg_Decision& out);
void to_vendor(const wire::AgentStatus& in, retreat_msg_AgentStatus& out);
void to_vendor(const wire::ArenaTelemetry& in, retreat_msg_ArenaTelemetry& out);
struct PosesScratch {
  std::vector<retreat_msg_RobotPose> robots;
  std::vector<retreat_msg_Point2> pickups;
  std::vector<retreat_msg_Point2> dropoffs;
};
void to_vendor(const wire::Poses& in, retreat_msg_Poses& out, PosesScratch& scratch);

wire::ProximityFrame to_plain(const retreat_msg_ProximityFrame& m);
wire::Decision to_plain(const retreat_msg_Decision& m);
wire::AgentStatus to_plain(const retreat_msg_AgentStatus& m);
wire::ArenaTelemetry to_plain(const retreat_msg_ArenaTelemetry& m);
wire::Poses to_plain(const retreat_msg_Poses& m);

}  // namespace retreat::transport::cyclonedds
