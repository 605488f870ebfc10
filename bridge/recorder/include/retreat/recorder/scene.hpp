#pragma once
/// @file
/// The arena drawn for Foxglove: each `poses` sample of a recording is also written as a
/// `foxglove.SceneUpdate` message (JSON, with the JSON Schema of @foxglove/schemas), so that
/// Foxglove's 3D panel draws the domain, the robots and the objects without configuration.
/// docs/recording.md, "Opening it elsewhere".

#include <cstdint>
#include <string>
#include <string_view>

#include "retreat/physics/params.hpp"
#include "retreat/wire/messages.hpp"

namespace retreat::recorder {

/// The JSON Schema of foxglove.SceneUpdate, from the npm package @foxglove/schemas (compiled in).
std::string_view scene_update_schema();

/// The frame every entity is drawn in (the arena's coordinates: the domain centred on the origin).
inline constexpr std::string_view scene_frame = "arena";

/// One SceneUpdate (JSON) for @p poses, stamped @p time_ns [ns since the epoch]: entity `domain`
/// (the outline of @p world's domain), entity `robots` (a cylinder of the footprint radius per
/// robot, coloured by phase: waiting grey, inside blue, retreating orange, departed faint; an
/// arrow along its heading, green when it carries an object, with its id above it) and entity
/// `objects` (pick-up points green, drop-off points blue).
std::string scene_update_json(const wire::Poses& poses, const physics::WorldParams& world, std::uint64_t time_ns);

}  // namespace retreat::recorder
