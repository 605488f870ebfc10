// Every DDS domain id a test or benchmark uses, in one place, checked at compile time.
//
// CTest runs the suites in parallel, so two tests that share a domain id hear each other. And a
// test on loopback must stay below domain 102: from there on the RTPS well-known ports
// (7400 + 250·domain + ...) lie in Linux's ephemeral port range (32768..60999), where any socket
// that takes a free port may take one of them. A Cyclone star agent (ParticipantIndex none) is
// such a socket: in CI one landed on a port a swarm on domain 140 announced itself to, and
// discovered three participants of another test. Hence the two rules, enforced below: blocks do
// not overlap, and only tests that run inside network namespaces they create themselves may use
// domains from 102 on.
//
// A new suite takes a free block here; the static_assert refuses an overlap or a loopback block
// from 102 on.

#pragma once

#include <array>
#include <string_view>

namespace retreat::testing {

/// A block of DDS domain ids that belongs to one suite: first .. first + count - 1.
struct DomainBlock {
  std::string_view suite;
  int first;
  int count;
  bool own_network_namespace = false;  ///< runs only inside network namespaces it creates

  /// The i-th id of the block; a constant expression refuses an index past the block.
  constexpr int at(int i) const { return i >= 0 && i < count ? first + i : throw "domain index outside its block"; }
  constexpr int last() const { return first + count - 1; }
};

namespace domains {

// Domain 0 is every program's default, left to real swarms on this host.
inline constexpr DomainBlock robot_link_cyclonedds{"robot link, Cyclone DDS", 1, 5};
inline constexpr DomainBlock pingpong_bench{"ping-pong benchmark (6 Fast DDS, 7 Cyclone DDS)", 6, 2};
inline constexpr DomainBlock arena_program{"arena program", 8, 1};
inline constexpr DomainBlock dds_profile_files{"DDS profile files in one process", 9, 1};
inline constexpr DomainBlock contract{"transport contract (by test name)", 10, 24};
inline constexpr DomainBlock launch_plans{"retreat-launch with run.plans", 34, 6};
inline constexpr DomainBlock cross_vendor{"cross-vendor wire", 40, 2};
inline constexpr DomainBlock dds_profiles{"DDS profiles", 42, 8};
inline constexpr DomainBlock launch{"retreat-launch", 50, 15};
inline constexpr DomainBlock security{"DDS Security", 65, 8};
inline constexpr DomainBlock faults{"faults", 73, 7};
inline constexpr DomainBlock agent_program{"agent program, Fast DDS", 80, 4};
inline constexpr DomainBlock recording{"recorded runs (retreat-record), one after another; also deploy/bench/record_overhead.sh", 84, 1};
inline constexpr DomainBlock agent_program_cyclonedds{"agent program, Cyclone DDS", 85, 4};
inline constexpr DomainBlock experiment{"retreat-experiment", 89, 1};
// The arena program's tests and the launcher's several-domains tests borrow these two blocks:
// the four executables hold the CTest resource lock dds_domains_90_97
// (tests/integration/CMakeLists.txt, launch.cmake), so none of them runs beside another.
inline constexpr DomainBlock robot_link_fastdds{"robot link, Fast DDS (and the arena program)", 90, 5};
inline constexpr DomainBlock mixed_swarm{"mixed real-and-simulated swarm (and the arena program)", 95, 3};
inline constexpr DomainBlock bridge{"retreat-bridge", 98, 3};
inline constexpr DomainBlock launch_star{"retreat-launch, a star beyond one port block", 101, 1};
inline constexpr DomainBlock multihost{"several hosts (network namespaces)", 150, 7, true};

inline constexpr std::array all{robot_link_cyclonedds, pingpong_bench, arena_program, dds_profile_files,
                                contract,              launch_plans,   cross_vendor,   dds_profiles,  launch,
                                security,              faults,         agent_program, recording,
                                agent_program_cyclonedds, experiment,
                                robot_link_fastdds,    mixed_swarm,    bridge,        launch_star,
                                multihost};

/// The lowest domain id whose well-known ports reach Linux's ephemeral range (32768..60999).
inline constexpr int first_in_ephemeral_ports = 102;

constexpr bool valid(const DomainBlock& b) {
  return b.first >= 1 && b.count >= 1 && b.last() <= 232 &&
         (b.own_network_namespace || b.last() < first_in_ephemeral_ports);
}

constexpr bool disjoint(const DomainBlock& a, const DomainBlock& b) {
  return a.last() < b.first || b.last() < a.first;
}

constexpr bool all_valid_and_disjoint() {
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!valid(all[i])) return false;
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      if (!disjoint(all[i], all[j])) return false;
    }
  }
  return true;
}

static_assert(all_valid_and_disjoint(),
              "a test's DDS domain block overlaps another, or is on loopback at 102 or above");

}  // namespace domains
}  // namespace retreat::testing
