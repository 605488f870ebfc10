#pragma once
/// @file
/// Deterministic seeding: every random stream in retreat is derived from the scenario seed,
/// the robot id and a stream tag, so that a run never depends on process layout or timing.

#include <cstdint>

namespace retreat {

/// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective mix of 64 bits.
constexpr std::uint64_t splitmix64(std::uint64_t x) noexcept {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// Named random streams, so that two consumers of the same robot never share a generator.
enum class Stream : std::uint64_t {
  agent_decision = 1,  ///< the agent's coin flips (Algorithm 1)
  robot_motion = 2,    ///< the arena's random walk for one robot
  world = 3,           ///< the arena's world-level draws (pick-up/drop-off points, influx)
  kinetic = 4,         ///< the kinetic world's encounter process for one robot
  sensor = 5,          ///< the arena's sensing noise for one robot (missed and false onsets)
};

/// Seed for one (scenario seed, robot id, stream) triple. Robot id -1 means "no robot".
constexpr std::uint64_t seed_for(std::uint64_t scenario_seed, std::int64_t robot_id,
                                 Stream stream) noexcept {
  return splitmix64(splitmix64(splitmix64(scenario_seed) ^ static_cast<std::uint64_t>(robot_id)) ^
                    static_cast<std::uint64_t>(stream));
}

}  // namespace retreat
