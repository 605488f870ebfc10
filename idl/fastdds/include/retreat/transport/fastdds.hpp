#pragma once
/// @file
/// The Fast DDS 2.9 implementation of the transport. This header includes no vendor header.

#include <cstddef>
#include <memory>
#include <optional>
#include <span>

#include "retreat/transport/transport.hpp"

namespace retreat::transport {

/// Creates a participant. Without a profile, DDS is pinned to loopback (UDPv4 on 127.0.0.1 only,
/// initial peer 127.0.0.1, no shared memory). With a profile file, the participant profile named
/// "retreat_participant" in that file is used. Throws std::invalid_argument on bad options or an
/// unusable profile, std::runtime_error when the middleware refuses.
std::unique_ptr<Transport> make_fastdds_transport(const ParticipantOptions& options);

/// Decodes one sample's serialized bytes (the CDR with its encapsulation header, as on the wire
/// and in a recording) with the generated Fast DDS type, as a Fast DDS reader would; nullopt if
/// they do not decode. Not validated (wire::validate does that).
std::optional<wire::AnyMessage> decode_fastdds(wire::MessageKind kind, std::span<const std::byte> bytes);

}  // namespace retreat::transport
