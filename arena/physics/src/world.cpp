#include "retreat/physics/world.hpp"

#include "world_kinetic.hpp"
#include "world_physical.hpp"

namespace retreat::physics {

std::unique_ptr<World> make_world(const WorldParams& params) {
  params.validate();
  if (params.encounter_model == EncounterModel::kinetic) {
    return std::make_unique<detail::KineticWorld>(params);
  }
  return std::make_unique<detail::PhysicalWorld>(params);
}

}  // namespace retreat::physics
