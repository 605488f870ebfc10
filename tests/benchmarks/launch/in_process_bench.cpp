// A whole swarm in one process (retreat::launch::run_in_memory: the arena's and every agent's
// own code over the in-memory transport, lockstep) against its bare world, N = 10³ .. 10⁵, in
// the kinetic and the physical world, measured in the same run.
//
// The scenario is deploy/scenarios/kinetic-1000.yaml with N robots in a square of N / 1.6 m²
// (its density, just above λ*), the paper's agents; physical: the same with
// arena.encounter_model = physical (three physics steps per tick). items = robot-ticks, so
// items_per_second of in_process/… over that of bare_world/… at the same N is the share of
// the world in the whole run. in_process's time is the run's loop only (the arena's own clock,
// summary.wall_seconds); building the swarm is the counter setup_s. real_time_x is simulated
// over wall time. deploy/bench/inprocess_scale.sh prints the table of docs/benchmarks.md.

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "retreat/launch/in_memory_run.hpp"
#include "retreat/physics/world.hpp"
#include "retreat/scenario/scenario.hpp"

namespace {

constexpr double density = 1.6;  // robots/m², kinetic-1000.yaml's

/// Ticks per in-process run: 1,000 (30 simulated seconds) kinetic, 300 (9 s) physical.
std::int64_t ticks_of(bool physical) { return physical ? 300 : 1000; }

/// How the agents are run: lockstep per tick, with plans, or with plans while every agent takes
/// a decision step every tick.
enum class Lockstep : std::int64_t { per_tick = 0, plans = 1, plans_deciding = 2 };

retreat::scenario::Scenario scenario_of(std::int64_t robots, bool physical, Lockstep lockstep = Lockstep::per_tick) {
  const double side = std::sqrt(static_cast<double>(robots) / density);
  std::vector<std::string> overrides = {
      "arena.robots_inside=" + std::to_string(robots), "arena.width=" + std::to_string(side),
      "arena.height=" + std::to_string(side),
      "run.duration=" + std::to_string(static_cast<double>(ticks_of(physical)) * 0.03)};
  if (physical) overrides.emplace_back("arena.encounter_model=physical");
  // The scenario says run.plans: true.
  overrides.emplace_back(lockstep == Lockstep::per_tick ? "run.plans=false" : "run.plans=true");
  if (lockstep == Lockstep::plans_deciding) {
    // With L = 90 s nobody takes a decision step within these runs, and a plan's frames before
    // the first one are taken in one go. Here every agent takes one every tick from tick 100
    // (L = 3 s), with a coin each, so a plan's every tick is stepped twice (looking ahead, then
    // acting on it); K_p = 0 (p = 0) keeps the swarm whole, so every run has the same robots.
    overrides.emplace_back("agent.L=3");
    overrides.emplace_back("agent.K_p=0");
  }
  return retreat::scenario::load(RETREAT_SCENARIOS "/kinetic-1000.yaml", overrides);
}

void bare_world(benchmark::State& state) {
  const auto s = scenario_of(state.range(0), state.range(1) != 0);
  auto world = retreat::physics::make_world(s.arena);
  for (auto _ : state) world->step_tick();
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void in_process(benchmark::State& state) {
  const auto s = scenario_of(state.range(0), state.range(1) != 0, static_cast<Lockstep>(state.range(2)));
  std::int64_t ticks = 0;
  std::uint64_t planned = 0;
  double loop = 0.0, total = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const auto run = retreat::launch::run_in_memory(s, nullptr, [] { return true; });
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    loop += run.summary.wall_seconds;
    ticks += run.summary.ticks;
    planned += run.summary.decisions_planned;
    state.SetIterationTime(run.summary.wall_seconds);
  }
  state.SetItemsProcessed(ticks * state.range(0));
  const auto runs = static_cast<double>(state.iterations());
  state.counters["setup_s"] = (total - loop) / runs;
  state.counters["real_time_x"] = static_cast<double>(ticks) * s.arena.tick_dt / loop;
  state.counters["planned"] = static_cast<double>(planned) / (static_cast<double>(ticks) * static_cast<double>(state.range(0)));
}

// Args: {robots, physical}.
BENCHMARK(bare_world)
    ->ArgsProduct({{1000, 10000, 100000}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
// Args: {robots, physical, lockstep}: lockstep 0 per tick, 1 event-driven (run.plans), 2 the
// same with every agent deciding every tick.
BENCHMARK(in_process)
    ->ArgsProduct({{1000, 10000, 100000}, {0, 1}, {0, 1, 2}})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
