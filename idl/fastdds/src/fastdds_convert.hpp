#pragma once
// Plain <-> Fast DDS generated types. Only this adapter sees the generated classes.

#include "retreat/wire/messages.hpp"
#include "retreat_msgs.h"

namespace retreat::transport::fastdds {

msg::ProximityFrame to_vendor(const wire::ProximityFrame& m);
msg::Decision to_vendor(const wire::Decision& m);
msg::AgentStatus to_vendor(const wire::AgentStatus& m);
msg::ArenaTelemetry to_vendor(const wire::ArenaTelemetry& m);
msg::Poses to_vendor(const wire::Poses& m);

wire::ProximityFrame to_plain(const msg::ProximityFrame& m);
wire::Decision to_plain(const msg::Decision& m);
wire::AgentStatus to_plain(const msg::AgentStatus& m);
wire::ArenaTelemetry to_plain(const msg::ArenaTelemetry& m);
wire::Poses to_plain(const msg::Poses& m);

}  // namespace retreat::transport::fastdds
