// In-process runs (--in-process): the scenario with the seed's overrides, run_in_memory into the
// run directory, a progress line, and the launcher's part of summary.json.

#include <chrono>

#include "retreat/launch/in_memory_run.hpp"
#include "retreat/scenario/scenario.hpp"
#include "progress.hpp"
#include "run.hpp"
#include "summary.hpp"

namespace retreat::launch {

RunOutcome run_in_process(const Plan& plan, std::uint64_t seed, const std::string& dir,
                          bool progress_line) {
  using Clock = std::chrono::steady_clock;
  const auto launch_start = Clock::now();
  auto s = scenario::load(plan.options.scenario_path, overrides_for_seed(plan, seed));
  s.dds.vendor = scenario::Vendor::inmemory;  // what scenario.yaml in the run directory records

  arena::RunRecorder recorder(dir, s, scenario::dump(s));
  recorder.flush_each_tick(false);  // nothing resumes an in-process run: flushed at its end
  const auto keep_going = [] { return stop_signal.load() == 0; };
  ProgressLine progress(s.name + " seed " + std::to_string(seed) + " in-process", s.run.duration);
  const auto show_progress = [&](const arena::ArenaNode& arena, double wall) {
    if (!progress_line || !progress.enabled() || (arena.tick() & 255) != 0) return;
    progress.show(arena::telemetry_message(arena.world().telemetry(), arena.agents_lost(),
                                           wall > 0 ? static_cast<double>(arena.tick()) / wall : 0.0));
  };
  const auto run = run_in_memory(s, &recorder, keep_going, show_progress);
  progress.finish();

  LaunchRecord record;
  record.dds = "inmemory";
  record.mode = "in-process";
  record.agents_started = run.agents_started;
  record.wall_seconds = std::chrono::duration<double>(Clock::now() - launch_start).count();
  record.arena_vendor = "inmemory";
  record.agent_vendors["inmemory"] = record.agents_started;
  RunOutcome out;
  out.summary = update_summary(dir, record);
  out.stopped = !keep_going();
  return out;
}

}  // namespace retreat::launch
