#pragma once
/// @file
/// One run of a scenario with one seed, in separate processes or in this one.

#include <atomic>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "retreat/launch/options.hpp"

namespace retreat::launch {

/// The signal (SIGINT, SIGTERM, SIGHUP) that asked the launcher to stop; 0 while none did.
extern std::atomic<int> stop_signal;

/// A run that failed (the arena failed, or left no summary): exit code 1.
class RunFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RunOutcome {
  bool stopped = false;    ///< a signal stopped it (the summary, if any, was still updated)
  nlohmann::json summary;  ///< the run directory's summary.json as updated by the launcher
};

/// Steps the arena and every agent in this process over the in-memory transport, in lockstep:
/// publish_tick, every agent's spin_once(0), collect_available, step. Writes `dir`. Draws the
/// progress line on a terminal if @p progress_line (not when several seeds run at once).
RunOutcome run_in_process(const Plan& plan, std::uint64_t seed, const std::string& dir,
                          bool progress_line = true);

/// Endless queue: agents started ahead of the robots that exist (ids only grow, one at a time),
/// so that each agent is up and discovered before its robot joins the queue. Should the arena
/// still publish a robot's first frame before the match, lockstep re-sends unanswered frames
/// until run.agent_timeout, and real time applies decisions whenever they come.
inline constexpr std::uint32_t endless_spare_agents = 4;

/// The agent processes a process run of @p s starts at once: one per robot inside or waiting,
/// and the endless queue's spares.
inline std::uint32_t agent_processes(const Plan& plan, const scenario::Scenario& s) {
  return s.arena.robots_inside + s.arena.robots_waiting + (plan.endless ? endless_spare_agents : 0);
}

/// Starts retreat-arena, one retreat-agent per robot (and the bridge), supervises them until
/// the arena exits, stops the rest, and updates `dir`/summary.json. Throws RunFailure.
RunOutcome run_processes(const Plan& plan, std::uint64_t seed, const std::string& dir, int domain);

}  // namespace retreat::launch
