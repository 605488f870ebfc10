#pragma once
/// @file
/// Deterministic sample contents for contract and cross-vendor tests: sample i of each kind is
/// a function of i alone, so a reader in another process can check every field.

#include <cstdint>
#include <string>

#include "retreat/wire/messages.hpp"

namespace retreat::testing {

inline wire::ProximityFrame frame_sample(std::uint32_t robot, std::int64_t i) {
  return {robot, i, 0.03 * static_cast<double>(i), static_cast<wire::Phase>(i % 4), i % 3 == 0,
          static_cast<std::uint32_t>(i % 5)};
}
inline wire::Decision decision_sample(std::uint32_t robot, std::int64_t i) {
  return {robot, i, 0.03 * static_cast<double>(i), i % 7 == 0};
}
inline wire::AgentStatus status_sample(std::uint32_t robot, std::int64_t i) {
  return {robot, i, 0.5 * static_cast<double>(i), i % 2 == 0, i % 3 == 0,
          static_cast<std::uint32_t>(i % 11), 0.25 * static_cast<double>(i % 13),
          0.001 * static_cast<double>(i), static_cast<std::uint64_t>(i) * 1000003ULL};
}
inline wire::ArenaTelemetry telemetry_sample(std::uint32_t arena, std::int64_t i) {
  return {arena,
          i,
          0.03 * static_cast<double>(i),
          static_cast<std::uint32_t>(i % 12),
          static_cast<std::uint32_t>(i % 4),
          static_cast<std::uint32_t>(i % 3),
          static_cast<std::uint32_t>(i % 9),
          static_cast<std::uint32_t>(i % 2),
          1.0 / (1.0 + static_cast<double>(i)),
          static_cast<std::uint64_t>(i) * 7ULL,
          1000.0 + static_cast<double>(i)};
}
inline wire::Poses poses_sample(std::uint32_t arena, std::int64_t i) {
  wire::Poses p;
  p.arena_id = arena;
  p.tick = i;
  p.time = 0.03 * static_cast<double>(i);
  for (std::int64_t k = 0; k < i % 13; ++k) {
    p.robots.push_back({static_cast<std::uint32_t>(k), 0.01f * static_cast<float>(k + i),
                        -0.02f * static_cast<float>(k), 0.1f * static_cast<float>(i % 31),
                        static_cast<wire::Phase>(k % 4), k % 2 == 1});
  }
  for (std::int64_t k = 0; k < i % 5; ++k) p.pickups.push_back({0.5f * static_cast<float>(k), 0.25f});
  for (std::int64_t k = 0; k < i % 3; ++k) p.dropoffs.push_back({-0.5f, 0.125f * static_cast<float>(k)});
  return p;
}

}  // namespace retreat::testing
