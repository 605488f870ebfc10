// One physics step of retreat::physics at fixed density, N = 10² .. 10⁵.
//
// The physical world steps with barrier certificates, neighbour grid, encounters and the
// collection task (everything a tick does; tick_dt = physics_dt so one iteration is one
// step). items_processed = robot-steps. Density 2 robots/m² (inside the paper's range), the
// Robotarium's platform numbers and γ = 10⁴ (params.hpp). The kinetic world's tick is measured
// beside it (items = robot-ticks).

#include <benchmark/benchmark.h>

#include <cmath>

#include "retreat/physics/world.hpp"

namespace {

using retreat::physics::WorldParams;

constexpr double density = 2.0;  // robots/m²

WorldParams world_of(std::int64_t robots, retreat::physics::EncounterModel model) {
  WorldParams p;
  p.encounter_model = model;
  p.shape = retreat::physics::DomainShape::rectangle;
  p.width = std::sqrt(static_cast<double>(robots) / density);
  p.height = p.width;
  p.robots_inside = static_cast<std::uint32_t>(robots);
  p.robots_waiting = 0;
  p.lambda_in = 0.0;
  p.tick_dt = p.physics_dt;
  p.tumble_rate = 0.1;
  return p;
}

void physical_step(benchmark::State& state) {
  auto world = retreat::physics::make_world(world_of(state.range(0), retreat::physics::EncounterModel::physical));
  for (int k = 0; k < 100; ++k) {  // leave the initial placement behind
    world->step_tick();
  }
  for (auto _ : state) {
    world->step_tick();
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["onsets_per_robot_step"] = benchmark::Counter(
      static_cast<double>(world->telemetry().onsets) /
      (static_cast<double>(state.range(0)) * static_cast<double>(world->telemetry().tick)));
}

void kinetic_tick(benchmark::State& state) {
  auto world = retreat::physics::make_world(world_of(state.range(0), retreat::physics::EncounterModel::kinetic));
  for (auto _ : state) {
    world->step_tick();
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

BENCHMARK(physical_step)->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(kinetic_tick)->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
