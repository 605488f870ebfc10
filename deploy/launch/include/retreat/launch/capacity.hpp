#pragma once
/// @file
/// Whether this host can hold a process run before anything starts: DDS participants per domain
/// (the discovery settings' participant indices), tasks (threads) and memory. A run that does not
/// fit is refused in one line naming the limit and the way out, instead of agents that fail to
/// find a port, are never discovered and are declared lost one by one.

#include <cstdint>
#include <optional>
#include <string>

#include "retreat/launch/options.hpp"

namespace retreat::launch {

/// How many participants of one domain on one host a process's DDS settings can discover.
struct DiscoveryLimit {
  /// At most this many participants in the domain on this host; none: not bounded by indices
  /// (a star: agents announce to the hub only and take free ports).
  std::optional<std::uint32_t> participants;
  std::string settings;  ///< what the limit comes from, for the refusal line
  /// At most this many agents in one swarm with these settings, whatever the indices: endpoint
  /// discovery is per participant, so the arena announces its writer and reader of every robot
  /// to every agent (2N² announcements). none: not measured to break.
  std::optional<std::uint32_t> agents = std::nullopt;
};

/// The most agents a Cyclone DDS swarm without participant indices (the star's agents) was
/// measured to run with on this 2-core machine, per domain: 300 matched in 17 s and all
/// answered; of 400, 69 answered within a minute (docs/benchmarks.md, "Discovery"). A swarm over
/// several domains (dds.domains) is counted per domain.
inline constexpr std::uint32_t cyclone_star_agents = 300;

/// The limit of @p vendor's settings: its built-in loopback settings when @p profile is empty
/// (participant indices 0..119: the ports a domain's block holds), else what the profile file
/// declares (Cyclone DDS: ParticipantIndex auto and MaxAutoParticipantIndex, none, or a fixed
/// index; Fast DDS: a discovery-server client, or maxInitialPeersRange). Elements inside XML
/// comments do not count. @throws std::invalid_argument if the file is not well-formed XML.
DiscoveryLimit discovery_limit(const std::string& vendor, const std::string& profile);

/// What the host allows and has, read from the kernel (tests pass their own).
struct HostLimits {
  std::uint64_t memory_available = 0;  ///< MemAvailable [bytes]
  std::uint64_t tasks_allowed = 0;     ///< min(RLIMIT_NPROC, kernel.threads-max, kernel.pid_max)
  std::uint64_t tasks_in_use = 0;      ///< every task on the host now (an upper bound of ours)
};

/// This host's limits now: /proc/meminfo, getrlimit(RLIMIT_NPROC), /proc/sys/kernel/threads-max,
/// /proc/sys/kernel/pid_max, /proc/loadavg. A value that cannot be read is left at its maximum
/// (it then limits nothing).
HostLimits read_host_limits();

/// Estimates per agent process, from measurements of idle and running agents on this machine
/// (docs/benchmarks.md, "Discovery": PSS 2.9–3.1 MiB; threads counted in /proc/<pid>/task):
/// memory with twice the measured PSS as headroom, threads as counted per vendor.
inline constexpr std::uint64_t agent_memory_estimate = 6u << 20;
std::uint32_t agent_threads(const std::string& vendor);

/// A range of UDP/TCP ports, first..last.
struct PortRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
};
/// Linux's default ephemeral ports, 32768..60999: where a socket bound to port 0 gets its port.
inline constexpr PortRange linux_default_ephemeral_ports{32768, 60999};
/// This host's ephemeral ports (/proc/sys/net/ipv4/ip_local_port_range; the default if unreadable).
PortRange read_ephemeral_ports();
/// The RTPS well-known ports of domain @p domain with the default port parameters: the block
/// 7400 + 250·domain .. 7400 + 250·domain + 249 (discovery and user data, every participant index).
PortRange well_known_ports(int domain);
/// Empty unless the well-known ports of domains @p first_domain .. first_domain + count - 1
/// overlap @p ephemeral; then one line saying so: any socket bound to a free port (a Cyclone DDS
/// star agent's, another program's) may take a port a participant needs, which then fails to
/// start or is not discovered. (A warning, not a refusal: most runs still find their ports free.)
std::optional<std::string> ephemeral_port_warning(int first_domain, int count, const PortRange& ephemeral);

/// Memory of one robot with its agent in an in-process run: the world's state of it, the agent
/// node and its in-memory participant. Measured as peak RSS with robots at the start (docs/deploy.md,
/// "Scenario limits"): 11.1 KiB a robot in the kinetic world (10⁶ robots: 10.6 GiB), 11.8 KiB in
/// the physical world (2·10⁴ robots); this is about 1.4 times that.
inline constexpr std::uint64_t in_process_robot_memory_estimate = 16u << 10;

/// How many seeds an in-process run of a plan takes at once on a host.
struct InProcessFit {
  unsigned jobs = 1;                   ///< seeds at once: the plan's, or fewer that fit
  std::optional<std::string> refusal;  ///< one line: not one run fits, or --jobs was given and does not
  std::optional<std::string> notice;   ///< one line: the default (the core count) was lowered to fit
};

/// The in-process counterpart of capacity_refusal: the robots at the start (arena.robots_inside +
/// arena.robots_waiting) with their agents, times the runs at once (the plan's jobs, at most one
/// per seed), against MemAvailable. A default --jobs is lowered to what fits; a given one that does
/// not fit is refused, naming the one that does. Robots that join later (an endless queue's, an
/// influx's) are not counted.
InProcessFit in_process_fit(const Plan& plan, const HostLimits& host);

/// Empty when a process run of @p plan with @p agents agent processes fits @p host; otherwise
/// the one line that says which limit it exceeds and what to do instead (for too many agents in
/// one domain, the `dds.domains` that would hold them).
std::optional<std::string> capacity_refusal(const Plan& plan, const scenario::Scenario& s, std::uint32_t agents,
                                            const HostLimits& host);

}  // namespace retreat::launch
