#pragma once
/// @file
/// The Cyclone DDS 0.10 implementation of the transport. This header includes no vendor header.

#include <cstddef>
#include <memory>
#include <optional>
#include <span>

#include "retreat/transport/transport.hpp"

namespace retreat::transport {

/// Creates a participant. Without a profile, DDS is pinned to loopback (interface `lo` with
/// multicast allowed). With a profile, the file's contents are the Cyclone XML configuration of
/// the domain. All participants of one process on one domain share that domain's configuration:
/// a second, different profile for the same domain is refused. Throws std::invalid_argument on
/// bad options or an unusable profile, std::runtime_error when the middleware refuses.
std::unique_ptr<Transport> make_cyclonedds_transport(const ParticipantOptions& options);

/// Decodes one sample's serialized bytes (the CDR with its encapsulation header, as on the wire
/// and in a recording) as a Cyclone DDS reader would; nullopt if they do not decode. Not
/// validated (wire::validate does that).
std::optional<wire::AnyMessage> decode_cyclonedds(wire::MessageKind kind, std::span<const std::byte> bytes);

}  // namespace retreat::transport
