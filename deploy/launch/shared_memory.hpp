#pragma once
/// @file
/// Fast DDS shared memory in /dev/shm. A Fast DDS participant with the shared-memory transport
/// (Fast DDS's default; retreat's own profiles and built-in settings never enable it) maps a
/// segment `fastrtps_<id>` (about 0.5 MiB, plus port segments `fastrtps_port<n>` and their
/// `sem.*_mutex` semaphores) and holds an exclusive flock() on `<segment>_el` while it lives. A
/// process that crashes leaves them all behind. When /dev/shm is full, a new Fast DDS process
/// with shared memory dies of SIGBUS on its first write to its segment, without a message
/// (measured with Fast DDS 2.9 on a 256 KiB tmpfs). `fastdds shm clean` removes stale segments;
/// Debian ships no `fastdds` tool, so the launcher does the same check itself.

#include <cstdint>
#include <string>

namespace retreat::launch {

struct ShmCleanup {
  std::uint32_t segments = 0;  ///< stale segments removed (each with its lock and semaphore)
  std::uint64_t bytes = 0;     ///< bytes freed
};

/// Removes every Fast DDS segment in `dir` whose owner is dead: its `<name>_el` lock file can be
/// flock()ed. A segment whose owner lives (the lock is held) and every other file stay.
ShmCleanup remove_stale_fastdds_segments(const std::string& dir = "/dev/shm");

/// True when the Fast DDS XML profile at `path` lets a participant use the shared-memory
/// transport: it declares an SHM transport, or keeps Fast DDS's built-in transports (UDP and
/// shared memory) by not setting useBuiltinTransports to false. An empty path (the adapter's
/// built-in UDP-only settings) does not.
bool profile_uses_shared_memory(const std::string& path);

/// Bytes free in the file system of `dir`.
std::uint64_t free_bytes(const std::string& dir);

/// What one Fast DDS participant with shared memory needs in /dev/shm, with headroom: its
/// 0.5 MiB segment and port segments [bytes].
inline constexpr std::uint64_t shm_bytes_per_participant = 1u << 20;

}  // namespace retreat::launch
