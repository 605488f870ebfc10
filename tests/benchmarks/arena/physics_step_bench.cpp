// One physics step of retreat::physics at fixed density, N = 10² .. 10⁵.
//
// The physical world steps with barrier certificates, neighbour grid, encounters and the
// collection task (everything a tick does; tick_dt = physics_dt so one iteration is one
// step). items_processed = robot-steps. Density 2 robots/m² (inside the paper's range), the
// Robotarium's platform numbers and γ = 10⁴ (params.hpp). The kinetic world's tick is measured
// beside it (items = robot-ticks). ellipse_root: the root behind an ellipse's nearest boundary
// point, by its defining bisection (/0) and by ellipse_root (/1, the same double), for points of
// the shipped 1.2 m × 0.8 m ellipse at 75–100 % of the way to its boundary, where the world asks
// (robots near the wall, robots driving out); items = roots.

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "retreat/core/rng.hpp"
#include "retreat/physics/ellipse_root.hpp"
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

void ellipse_root(benchmark::State& state) {
  struct Point {
    double r0, z0, z1, g;
  };
  const double e0 = 1.2;
  const double e1 = 0.8;
  retreat::Rng rng(3);
  std::vector<Point> points;
  for (int k = 0; k < 4096; ++k) {
    const double t = rng.uniform(0.01, 1.56);  // the first quadrant, off the axes
    const double scale = rng.uniform(0.75, 1.0);
    const double z0 = std::cos(t) * scale;
    const double z1 = std::sin(t) * scale;
    points.push_back({(e0 / e1) * (e0 / e1), z0, z1, z0 * z0 + z1 * z1 - 1.0});
  }
  const bool fast = state.range(0) == 1;
  std::size_t k = 0;
  for (auto _ : state) {
    const Point& p = points[k++ % points.size()];
    benchmark::DoNotOptimize(fast ? retreat::physics::ellipse_root(p.r0, p.z0, p.z1, p.g)
                                  : retreat::physics::ellipse_root_by_bisection(p.r0, p.z0, p.z1, p.g));
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(physical_step)->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(kinetic_tick)->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(ellipse_root)->Arg(0)->Arg(1)->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
