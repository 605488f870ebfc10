#pragma once
/// @file
/// Picks a transport implementation by name at run time.

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "retreat/transport/transport.hpp"

namespace retreat::transport {

/// Names accepted by make_transport in this build: "fastdds" and/or "cyclonedds" (when built)
/// and "inmemory".
std::vector<std::string> available_vendors();

/// The DDS vendors of this build (what `--dds` accepts).
std::vector<std::string> dds_vendors();

/// Creates a participant with the named implementation. Throws std::invalid_argument with one
/// line naming the value and the allowed ones for an unknown name, and passes on the
/// implementation's errors.
std::unique_ptr<Transport> make_transport(std::string_view vendor, const ParticipantOptions& options);

/// Decodes one sample's serialized bytes (CDR with its encapsulation header: a recording's
/// message) with a DDS vendor's generated code (Fast DDS's when built, else Cyclone DDS's), as a
/// reader of that vendor would; nullopt if they do not decode. The caller validates
/// (wire::validate). Throws std::logic_error in a build without DDS.
std::optional<wire::AnyMessage> decode_serialized(wire::MessageKind kind, std::span<const std::byte> bytes);

}  // namespace retreat::transport
