#include "retreat/launch/options.hpp"

#include "retreat/core/paths.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <filesystem>

#include "retreat/transport/factory.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::launch {
namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& i : items) out += (out.empty() ? "" : ", ") + i;
  return out;
}

bool executable(const std::string& path) { return ::access(path.c_str(), X_OK) == 0; }

bool sets_key(const std::vector<std::string>& overrides, const std::string& key) {
  return std::any_of(overrides.begin(), overrides.end(),
                     [&](const std::string& o) { return o.rfind(key + "=", 0) == 0; });
}

}  // namespace

std::string VendorPlan::agent(std::uint32_t index) const {
  if (label != "mixed") return arena;
  return index % 2 == 0 ? "fastdds" : "cyclonedds";
}

std::vector<std::string> overrides_for_seed(const Plan& plan, std::uint64_t seed) {
  auto out = plan.overrides;
  out.push_back("seed=" + std::to_string(seed));
  return out;
}

namespace {

/// --seeds A:B into plan.seeds (several runs); --seed with --seeds is refused.
void plan_seeds(const LaunchOptions& o, Plan& plan) {
  if (!o.seeds.empty() && o.seed) {
    throw UsageError("--seed " + std::to_string(*o.seed) + " with --seeds " + o.seeds +
                     ": give one or the other");
  }
  if (o.seeds.empty()) return;
  const auto range = parse_seed_range(o.seeds);
  for (auto s = range.first;; ++s) {
    plan.seeds.push_back(s);
    if (s == range.last) break;
  }
  plan.multi_seed = true;
}

/// --dds (a built vendor, or `mixed` where both are built; not in process) and --domain.
void check_middleware(const LaunchOptions& o) {
  const auto vendors = transport::dds_vendors();
  auto built = [&](const std::string& v) { return std::find(vendors.begin(), vendors.end(), v) != vendors.end(); };
  if (!o.dds.empty()) {
    if (o.in_process) {
      throw UsageError("--dds '" + o.dds + "': not used with --in-process (one process over the "
                       "in-memory transport)");
    }
    if (o.dds != "mixed" && !built(o.dds)) {
      auto allowed = vendors;
      if (vendors.size() == 2) allowed.emplace_back("mixed");
      throw UsageError("--dds '" + o.dds + "': must be one of " + join(allowed));
    }
    if (o.dds == "mixed" && vendors.size() != 2) {
      throw UsageError("--dds 'mixed': this build has only " + join(vendors) +
                       " (mixed needs Fast DDS and Cyclone DDS)");
    }
  }
  if (o.domain && (*o.domain < 0 || *o.domain > transport::max_domain_id)) {
    throw UsageError("--domain " + std::to_string(*o.domain) + ": must be an integer in 0.." +
                     std::to_string(transport::max_domain_id));
  }
}

/// The scenario with every override, exactly as the children will resolve it (the first seed's);
/// plan.overrides keep no seed: overrides_for_seed() appends it.
void resolve_scenario(const LaunchOptions& o, Plan& plan) {
  plan.overrides = o.overrides;
  if (!o.dds.empty() && o.dds != "mixed") plan.overrides.push_back("dds.vendor=" + o.dds);
  if (o.domain) plan.overrides.push_back("dds.domain=" + std::to_string(*o.domain));
  // --seed N, or the scenario's own seed (read below).
  if (!plan.multi_seed && o.seed) plan.overrides.push_back("seed=" + std::to_string(*o.seed));
  auto first = plan.overrides;
  if (plan.multi_seed) first.push_back("seed=" + std::to_string(plan.seeds.front()));
  plan.scenario = scenario::load(o.scenario_path, first);
  if (!plan.multi_seed) plan.seeds.push_back(plan.scenario.seed);
  std::erase_if(plan.overrides, [](const std::string& s) { return s.rfind("seed=", 0) == 0; });
  plan.endless = plan.scenario.arena.queue == physics::QueueKind::endless;
}

/// --jobs: 1..scenario::max_jobs; more than one only in process (process runs would share the host's
/// DDS ports, its cores and the run's domain). Default: the core count in process, else 1.
void plan_jobs(const LaunchOptions& o, Plan& plan) {
  if (o.jobs) scenario::check_jobs(*o.jobs);
  if (o.jobs && *o.jobs > 1 && !o.in_process) {
    throw UsageError("--jobs " + std::to_string(*o.jobs) +
                     ": only --in-process runs seeds at once (process runs take one at a time)");
  }
  plan.jobs = o.jobs ? *o.jobs : (o.in_process ? scenario::core_count() : 1u);
}

/// --in-process: lockstep, no DDS Security, no recorder.
void plan_in_process(Plan& plan) {
  if (!plan.options.record.empty()) {
    throw UsageError("--record '" + plan.options.record + "': records DDS traffic; not used with "
                     "--in-process (no DDS; the run directory's CSV files record the run)");
  }
  if (plan.scenario.run.recorders > 0) {
    throw UsageError("run.recorders = " + std::to_string(plan.scenario.run.recorders) +
                     ": --in-process runs have no recorder to wait for (use 0)");
  }
  if (plan.scenario.dds.security == scenario::Security::on) {
    throw UsageError("dds.security = on: not used with --in-process (the in-memory transport has "
                     "no DDS Security)");
  }
  plan.vendors = {"inmemory", "inmemory"};
  if (plan.scenario.run.mode != scenario::RunMode::lockstep) {
    throw UsageError("run.mode = " + std::string(retreat::name_of(plan.scenario.run.mode)) +
                     ": --in-process steps the arena and the agents in lockstep only");
  }
}

/// --record FILE: retreat-record beside the run, and every process waits for it (run.recorders).
void plan_recording(const LaunchOptions& o, const std::string& dir, Plan& plan) {
  const std::string what = "--record '" + o.record + "'";
  const auto parent = std::filesystem::absolute(o.record).parent_path();
  if (!std::filesystem::is_directory(parent)) {
    throw UsageError(what + ": the directory '" + parent.string() + "' does not exist");
  }
  if (std::filesystem::is_directory(o.record)) {
    throw UsageError(what + ": is a directory (give the MCAP file to write, e.g. run.mcap)");
  }
  plan.record_exe = dir + "/retreat-record";
  if (!executable(plan.record_exe)) {
    throw UsageError("'" + plan.record_exe + "': no such program (--record needs retreat-record next "
                     "to retreat-launch, or in --bin-dir)");
  }
  plan.overrides.push_back("run.recorders=1");
  plan.scenario.run.recorders = 1;
}

/// Process mode: the vendors, the domain, and the programs to start.
void plan_processes(const LaunchOptions& o, const std::string& self_dir, Plan& plan) {
  // --dds names a vendor (already in the scenario through dds.vendor) or the launcher's `mixed`.
  const bool mixed = o.dds == "mixed";
  const bool secure = plan.scenario.dds.security == scenario::Security::on;
  if (!mixed && plan.scenario.dds.vendor == scenario::Vendor::inmemory) {
    throw UsageError("dds.vendor = inmemory: separate processes need fastdds or cyclonedds "
                     "(or use --in-process)");
  }
  if (secure && mixed) {
    // docs/security.md: Fast DDS 2.9 and Cyclone DDS 0.10 do not complete secure handshakes
    // with each other reliably.
    throw UsageError("--dds mixed: not with dds.security = on (secure handshakes between Fast DDS "
                     "and Cyclone DDS fail in these versions; see docs/security.md)");
  }
  const std::string vendor(retreat::name_of(plan.scenario.dds.vendor));  // the children's --dds
  plan.vendors = mixed ? VendorPlan{"mixed", "cyclonedds"} : VendorPlan{vendor, vendor};
  // Every child resolves the PKI directory from its own working directory: make it absolute.
  if (secure) {
    plan.overrides.push_back("dds.security_dir=" +
                             std::filesystem::absolute(plan.scenario.dds.security_dir).string());
  }
  // The domain: --domain, or --set dds.domain=N; otherwise a free one is picked at run time.
  if (o.domain || sets_key(o.overrides, "dds.domain")) plan.domain = plan.scenario.dds.domain;
  const std::string dir = o.bin_dir.empty() ? self_dir : o.bin_dir;
  plan.arena_exe = dir + "/retreat-arena";
  plan.agent_exe = dir + "/retreat-agent";
  for (const auto& exe : {plan.arena_exe, plan.agent_exe}) {
    if (!executable(exe)) {
      throw UsageError("'" + exe + "': no such program (retreat-launch looks next to itself" +
                       std::string(o.bin_dir.empty() ? "; use --bin-dir DIR" : " in --bin-dir") + ")");
    }
  }
  for (const auto& name : transport::dds_vendors()) {
    const auto single = plan.agent_exe + "-" + name;
    if (executable(single)) plan.single_vendor_agent_exe[name] = single;
  }
  if (!o.record.empty()) plan_recording(o, dir, plan);
  if (!o.no_bridge) {
    const auto bridge = dir + "/retreat-bridge";
    if (executable(bridge)) {
      plan.bridge_exe = bridge;
    } else {
      plan.bridge_missing = true;
    }
  }
}

}  // namespace

const std::string& agent_program(const Plan& plan, const std::string& vendor) {
  const auto it = plan.single_vendor_agent_exe.find(vendor);
  return it != plan.single_vendor_agent_exe.end() ? it->second : plan.agent_exe;
}

std::string recording_path(const Plan& plan, std::uint64_t seed) {
  if (plan.options.record.empty()) return {};
  auto path = std::filesystem::absolute(plan.options.record);
  if (plan.multi_seed) {
    path.replace_filename(path.stem().string() + ".seed" + std::to_string(seed) +
                          path.extension().string());
  }
  return path.string();
}

Plan make_plan(const LaunchOptions& options, const std::string& self_dir) {
  Plan plan;
  plan.options = options;
  const auto& o = options;
  // The scenario file first: everything else is about it.
  if (!retreat::is_regular_file(o.scenario_path)) {
    throw UsageError("SCENARIO '" + o.scenario_path + "': no such file (a YAML scenario file)");
  }
  plan_seeds(o, plan);
  check_middleware(o);
  resolve_scenario(o, plan);
  if (!o.arena_profile.empty()) {
    if (o.in_process) throw UsageError("--arena-profile: not used with --in-process (no DDS)");
    if (!retreat::is_regular_file(o.arena_profile)) {
      throw UsageError("--arena-profile '" + o.arena_profile + "': no such file (a DDS XML profile "
                       "for the arena, e.g. deploy/dds/fastdds-discovery-server-hub.xml)");
    }
  }
  if (o.in_process) {
    plan_in_process(plan);
  } else {
    plan_processes(o, self_dir, plan);
  }
  plan_jobs(o, plan);
  return plan;
}

}  // namespace retreat::launch
