#pragma once
/// @file
/// A whole swarm in this process: the arena's and every agent's own code (retreat::arena_node,
/// retreat::agent_node) over the in-memory transport, stepped in lockstep. No files of its own,
/// no clock in the result: the launcher's --in-process runs and the portability check
/// (tests/portability) both call it.

#include <cstdint>
#include <functional>

#include "retreat/arena/arena_node.hpp"
#include "retreat/scenario/params.hpp"

namespace retreat::launch {

struct InMemoryRun {
  arena::RunSummary summary;        ///< the arena's (trajectory hash, ticks, agents lost, ...)
  std::uint32_t agents_started = 0;  ///< robots that have had an agent
};

/// Runs @p s to its end (or until @p keep_going says no) with the lockstep semantics of the
/// multi-process run: tick k's frames go out, every live agent answers tick k, then the world
/// steps; so the trajectory hash is the same as with processes. @p recorder may be null (no run
/// directory). @p on_tick is called after every step with the arena and the wall seconds since
/// the first tick (for a progress line).
InMemoryRun run_in_memory(const scenario::Scenario& s, arena::RunRecorder* recorder,
                          const std::function<bool()>& keep_going,
                          const std::function<void(const arena::ArenaNode&, double)>& on_tick = {});

}  // namespace retreat::launch
