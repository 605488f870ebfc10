#include "retreat/launch/capacity.hpp"

#include <sys/resource.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace retreat::launch {
namespace {

/// The participant indices a domain's block of well-known ports holds (ports 7410 + 250·domain +
/// 2·index up to the next domain's block), and what the adapters' built-in settings announce to.
constexpr std::uint32_t builtin_indices = 120;

std::string trimmed(const char* text) {
  std::string s = text != nullptr ? text : "";
  const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), space));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), space).base(), s.end());
  return s;
}

/// The text of the first element named @p name anywhere below @p node (comments are not
/// elements), or nullopt.
std::optional<std::string> first_text(const tinyxml2::XMLNode& node, const char* name) {
  for (const auto* child = node.FirstChildElement(); child != nullptr; child = child->NextSiblingElement()) {
    if (std::string_view(child->Name()) == name) return trimmed(child->GetText());
    if (auto below = first_text(*child, name)) return below;
  }
  return std::nullopt;
}

std::optional<std::uint32_t> number(const std::string& text) {
  try {
    std::size_t used = 0;
    const auto v = std::stoul(text, &used);
    if (used == text.size() && v <= std::numeric_limits<std::uint32_t>::max()) return static_cast<std::uint32_t>(v);
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

/// @p text with Cyclone DDS's expansion of `${NAME}` and `${NAME:-default}` from the environment
/// (as the process this launcher starts would see it); nullopt for forms it does not know.
std::optional<std::string> expanded(const std::string& text) {
  std::string out;
  for (std::size_t at = 0; at < text.size();) {
    if (text.compare(at, 2, "${") != 0) {
      out += text[at++];
      continue;
    }
    const auto end = text.find('}', at);
    if (end == std::string::npos) return std::nullopt;
    const std::string inner = text.substr(at + 2, end - at - 2);
    const auto dash = inner.find(":-");
    const std::string name = inner.substr(0, dash);
    if (name.empty() || name.find_first_of(":+?$") != std::string::npos) return std::nullopt;
    const char* value = std::getenv(name.c_str());
    if (value != nullptr && *value != '\0') {
      out += value;
    } else if (dash != std::string::npos) {
      out += inner.substr(dash + 2);
    }
    at = end + 1;
  }
  return out;
}

DiscoveryLimit cyclone_limit(const tinyxml2::XMLDocument& doc, const std::string& profile) {
  const auto written = first_text(doc, "ParticipantIndex");
  const auto index = written ? expanded(*written) : std::nullopt;
  if (written && !index) return {std::nullopt, profile};  // nothing the launcher can count: not refused
  // Cyclone DDS 0.10's default is "none": free ports, no index to run out of.
  if (!index || *index == "none") {
    return {std::nullopt, profile + " (ParticipantIndex none)", cyclone_star_agents};
  }
  if (*index == "auto") {
    const auto max_written = first_text(doc, "MaxAutoParticipantIndex");
    const auto max_text = max_written ? expanded(*max_written) : std::optional<std::string>("9");  // Cyclone's default
    const auto max_number = max_text ? number(*max_text) : std::nullopt;
    if (!max_number) return {std::nullopt, profile};
    const std::uint32_t max = std::min<std::uint32_t>(*max_number, 1u << 20);
    return {max + 1, profile + " (ParticipantIndex auto, MaxAutoParticipantIndex " + std::to_string(max) + ")"};
  }
  // A fixed index (a hub's): one participant per host with this file.
  return {1, profile + " (a fixed ParticipantIndex " + *index + ")"};
}

DiscoveryLimit fastdds_limit(const tinyxml2::XMLDocument& doc, const std::string& profile) {
  const auto protocol = first_text(doc, "discoveryProtocol");
  if (protocol && (*protocol == "CLIENT" || *protocol == "SUPER_CLIENT")) {
    return {std::nullopt, profile + " (a discovery-server " + *protocol + ")"};
  }
  if (const auto range = first_text(doc, "maxInitialPeersRange")) {
    if (const auto n = number(*range)) {
      return {*n, profile + " (SIMPLE discovery to initial peers, maxInitialPeersRange " + *range + ")"};
    }
  }
  return {std::nullopt, profile};  // nothing the launcher can count: not refused
}

std::optional<std::uint64_t> read_number(const std::string& path) {
  std::ifstream in(path);
  std::uint64_t v = 0;
  if (in >> v) return v;
  return std::nullopt;
}

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

}  // namespace

DiscoveryLimit discovery_limit(const std::string& vendor, const std::string& profile) {
  if (profile.empty()) {
    return {builtin_indices, "the built-in loopback settings of " + vendor + " (participant indices 0.." +
                                 std::to_string(builtin_indices - 1) + ")"};
  }
  std::ifstream in(profile);
  std::stringstream text;
  text << in.rdbuf();
  tinyxml2::XMLDocument doc;
  if (!in || doc.Parse(text.str().c_str()) != tinyxml2::XML_SUCCESS) {
    throw std::invalid_argument("dds.profile '" + profile + "': not a well-formed XML file (" +
                                (in ? std::string(doc.ErrorStr()) : std::string("cannot be read")) + ")");
  }
  return vendor == "cyclonedds" ? cyclone_limit(doc, profile) : fastdds_limit(doc, profile);
}

HostLimits read_host_limits() {
  HostLimits h;
  h.memory_available = std::numeric_limits<std::uint64_t>::max();
  std::ifstream meminfo("/proc/meminfo");
  for (std::string key; meminfo >> key;) {
    std::uint64_t kib = 0;
    meminfo >> kib;
    if (key == "MemAvailable:") {
      h.memory_available = kib * 1024;
      break;
    }
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  h.tasks_allowed = std::numeric_limits<std::uint64_t>::max();
  rlimit nproc{};
  if (::getrlimit(RLIMIT_NPROC, &nproc) == 0 && nproc.rlim_cur != RLIM_INFINITY) h.tasks_allowed = nproc.rlim_cur;
  for (const char* path : {"/proc/sys/kernel/threads-max", "/proc/sys/kernel/pid_max"}) {
    if (const auto v = read_number(path)) h.tasks_allowed = std::min(h.tasks_allowed, *v);
  }
  // /proc/loadavg: "0.20 0.18 0.12 1/80 11206": runnable/total tasks.
  std::ifstream loadavg("/proc/loadavg");
  std::string a, b, c, tasks;
  if (loadavg >> a >> b >> c >> tasks) {
    if (const auto slash = tasks.find('/'); slash != std::string::npos) {
      h.tasks_in_use = std::stoull(tasks.substr(slash + 1));
    }
  }
  return h;
}

PortRange read_ephemeral_ports() {
  std::ifstream in("/proc/sys/net/ipv4/ip_local_port_range");
  PortRange r;
  if (in >> r.first >> r.last && r.first <= r.last) return r;
  return linux_default_ephemeral_ports;
}

// RTPS 2.x §9.6.1.1 with PB = 7400, DG = 250: a domain's ports are PB + DG·domain + offsets
// d0..d3 (0, 10, 1, 11) + PG·index (PG = 2), all inside its block of DG.
constexpr std::uint32_t port_base = 7400;
constexpr std::uint32_t domain_gain = 250;

PortRange well_known_ports(int domain) {
  const auto first = port_base + domain_gain * static_cast<std::uint32_t>(domain);
  return {first, first + domain_gain - 1};
}

std::optional<std::string> ephemeral_port_warning(int first_domain, int count, const PortRange& ephemeral) {
  const int last_domain = first_domain + count - 1;
  const PortRange used{well_known_ports(first_domain).first, well_known_ports(last_domain).last};
  if (used.last < ephemeral.first || used.first > ephemeral.last) return std::nullopt;
  // The lowest domain whose block reaches the ephemeral range: the least d with
  // well_known_ports(d).last = well_known_ports(0).last + DG·d ≥ its first port.
  const std::uint32_t base_last = well_known_ports(0).last;
  const std::uint32_t reach = ephemeral.first > base_last ? ephemeral.first - base_last : 0;
  const std::uint32_t lowest_unsafe = (reach + domain_gain - 1) / domain_gain;
  std::ostringstream line;
  line << "DDS domain" << (count > 1 ? "s " : " ") << first_domain;
  if (count > 1) line << ".." << last_domain;
  line << " use" << (count > 1 ? "" : "s") << " the well-known ports " << used.first << ".." << used.last
       << ", inside this host's ephemeral ports " << ephemeral.first << ".." << ephemeral.last
       << " (/proc/sys/net/ipv4/ip_local_port_range): any socket bound to a free port may take one a participant "
          "needs; prefer domain ids below "
       << lowest_unsafe << " (docs/deploy.md, \"Domain ids\")";
  return line.str();
}

std::uint32_t agent_threads(const std::string& vendor) {
  // Counted in /proc/<pid>/task of an agent waiting for its arena (Fast DDS 2.9: 7, Cyclone DDS
  // 0.10: 8), plus two for what a run and DDS Security add.
  return vendor == "fastdds" ? 9 : 10;
}

std::optional<std::string> capacity_refusal(const Plan& plan, const scenario::Scenario& s, std::uint32_t agents,
                                            const HostLimits& host) {
  // Everyone in the domain on this host besides the agents: the arena, the launcher's telemetry
  // reader, the bridge, the recorder.
  std::vector<std::string> others = {"the arena", "the launcher"};
  if (!plan.bridge_exe.empty()) others.emplace_back("the bridge");
  if (!plan.record_exe.empty()) others.emplace_back("the recorder");
  // Discovery is per domain: with dds.domains K, a domain holds every K-th robot's agent and one
  // participant of each of the others.
  const auto domains = static_cast<std::uint32_t>(s.dds.domains);
  const std::uint32_t per_domain = (agents + domains - 1) / domains;
  const std::uint32_t participants = per_domain + static_cast<std::uint32_t>(others.size());
  std::string who = std::to_string(per_domain) + " agents";
  for (std::size_t i = 0; i < others.size(); ++i) who += (i + 1 == others.size() ? " and " : ", ") + others[i];
  const std::string where = domains == 1 ? "in one domain" : "in each of " + std::to_string(domains) + " domains";
  // The way out for a swarm too big for one domain's discovery: enough domains that each holds
  // at most `fits` agents.
  const auto more_domains = [&](std::uint32_t fits) {
    const std::uint32_t needed = fits == 0 ? 0 : (agents + fits - 1) / fits;
    if (fits == 0 || needed > static_cast<std::uint32_t>(wire::max_domains)) return std::string();
    return ", or spread the swarm over " + std::to_string(needed) + " domains (--set dds.domains=" +
           std::to_string(needed) + ")";
  };
  // Agents are the many: their settings bound the domain (a star's hub has a fixed index).
  std::vector<std::string> vendors;
  for (std::uint32_t r = 0; r < std::min<std::uint32_t>(agents, 2); ++r) vendors.push_back(plan.vendors.agent(r));
  for (const auto& vendor : vendors) {
    const auto limit = discovery_limit(vendor, s.dds.profile);
    if (limit.participants && participants > *limit.participants) {
      const std::uint32_t fits = *limit.participants > others.size() ? *limit.participants - static_cast<std::uint32_t>(others.size()) : 0;
      return std::to_string(participants) + " DDS participants (" + who + ") " + where + " on this host, but " +
             limit.settings + " discover at most " + std::to_string(*limit.participants) +
             ": use the star profiles (deploy/dds/*-star-*.xml or the Fast DDS discovery-server pair, "
             "with --arena-profile; docs/dds-profiles.md)" + more_domains(fits) + ", or fewer agents per host";
    }
    if (limit.agents && per_domain > *limit.agents) {
      return std::to_string(per_domain) + " agents " + where + " with " + limit.settings +
             ", but such a swarm was measured to run with at most " + std::to_string(*limit.agents) +
             " per domain (the arena announces its 2 endpoints per robot to every agent of the domain: 2N^2 "
             "announcements; docs/benchmarks.md, \"Discovery\")" + more_domains(*limit.agents) +
             ", or run fewer agents per swarm";
    }
  }
  std::uint64_t threads = 0;
  for (std::uint32_t r = 0; r < agents; ++r) threads += agent_threads(plan.vendors.agent(r));
  if (host.tasks_in_use + threads > host.tasks_allowed) {
    return std::to_string(agents) + " agent processes need about " + std::to_string(threads) +
           " threads, and this host has " + std::to_string(host.tasks_in_use) + " tasks of the " +
           std::to_string(host.tasks_allowed) +
           " it allows (ulimit -u, kernel.threads-max, kernel.pid_max): raise the limit, or spread the "
           "agents over several hosts";
  }
  const std::uint64_t memory = static_cast<std::uint64_t>(agents) * agent_memory_estimate;
  if (memory > host.memory_available) {
    return std::to_string(agents) + " agent processes need about " + mib(memory) + " of memory and " +
           mib(host.memory_available) + " is available: spread the agents over several hosts";
  }
  return std::nullopt;
}

InProcessFit in_process_fit(const Plan& plan, const HostLimits& host) {
  const auto& arena = plan.scenario.arena;
  const std::uint64_t robots = std::uint64_t{arena.robots_inside} + arena.robots_waiting;
  const std::uint64_t per_run = robots * in_process_robot_memory_estimate;
  const auto wanted = static_cast<unsigned>(std::min<std::size_t>(plan.jobs, std::max<std::size_t>(plan.seeds.size(), 1)));
  const std::uint64_t fits = per_run == 0 ? wanted : std::min<std::uint64_t>(wanted, host.memory_available / per_run);
  const std::string need = std::to_string(robots) + " robots (arena.robots_inside + arena.robots_waiting) with their agents need about " +
                           mib(per_run) + " of memory a run";
  const std::string have = mib(host.memory_available) + " is available (MemAvailable)";
  InProcessFit fit;
  fit.jobs = static_cast<unsigned>(fits);
  if (fits == 0) {
    fit.refusal = need + " in process, and " + have + ": run fewer robots, or the swarm as processes spread over several hosts";
  } else if (fits < wanted && plan.options.jobs) {
    fit.refusal = "--jobs " + std::to_string(*plan.options.jobs) + ": " + need + ", " + std::to_string(wanted) +
                  " at once about " + mib(per_run * wanted) + ", and " + have + ": at most --jobs " + std::to_string(fits) +
                  " fits";
  } else if (fits < wanted) {
    fit.notice = std::to_string(fits) + (fits == 1 ? " seed" : " seeds") + " at a time, not " + std::to_string(wanted) +
                 " (by default one per core): " + need + ", and " + have;
  }
  return fit;
}

}  // namespace retreat::launch
