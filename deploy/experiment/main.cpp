// retreat-experiment: reproduces the paper's results and compares controllers, one subcommand
// each, every one writing a run directory with its data (CSV, JSON) and report.html (figures,
// self-contained):
//   encounters   inter-encounter and encounter-resolution times, fitted ρ (MODEL.md §2, §6)
//   throughput   simulated T(λ)λ over a grid of λ against the CTMC curve (MODEL.md §3)
//   robotarium   population against time over many seeds (agent processes, in-process, endless
//                queue, kinetic world), run by retreat-launch
//   controllers  every registered controller against paper on the same seeds (J of MODEL.md §4)
// Reads the shipped scenarios (--scenarios DIR); runs retreat-launch (beside this program, or
// --launcher) as a child process. No DDS of its own: the launcher and its children use DDS in
// `robotarium`'s process set-up only.
//
// Exit codes: 0 done; 1 a run failed; 2 bad input (nothing was started); 128 + signal when
// SIGINT/SIGTERM/SIGHUP stopped it (the launcher is stopped first).

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>

#include "launch.hpp"
#include "retreat/core/paths.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"
#include "subcommands.hpp"

namespace {

using namespace retreat::experiment;
namespace fs = std::filesystem;

extern "C" void on_signal(int signo) { stop_signal.store(signo); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
}

std::string self_dir() {
  std::error_code ec;
  const auto exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

/// The shipped scenarios: installed beside bin/ (share/retreat/scenarios), else the source tree.
std::string default_scenarios() {
  const auto installed = fs::path(self_dir()) / ".." / "share" / "retreat" / "scenarios";
  if (retreat::is_directory(installed.string())) return fs::weakly_canonical(installed).string();
  return RETREAT_SOURCE_SCENARIOS;
}

std::string default_out(const std::string& subcommand) {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  return "runs/experiment-" + subcommand + "-" + stamp;
}

/// --out, --quick, --scenarios, --launcher on `sub`.
void add_common(CLI::App* sub, Common& c) {
  sub->add_option("--out", c.out_dir, "run directory, new or empty (default: runs/experiment-<name>-<time>)");
  sub->add_flag("--quick", c.quick, "the reduced size: well under two minutes on two cores");
  sub->add_option("--scenarios", c.scenarios_dir, "directory of the shipped scenarios (default: " +
                                                      default_scenarios() + ")");
  sub->add_option("--launcher", c.launcher, "retreat-launch to run (default: beside this program)");
}

void finish_common(Common& c, const std::string& name) {
  if (c.out_dir.empty()) c.out_dir = default_out(name);
  if (c.scenarios_dir.empty()) c.scenarios_dir = default_scenarios();
  if (!retreat::is_directory(c.scenarios_dir)) {
    throw UsageError("--scenarios '" + c.scenarios_dir + "': no such directory (the shipped scenarios)");
  }
  if (c.launcher.empty()) c.launcher = self_dir() + "/retreat-launch";
}

void require_launcher(const Common& c) {
  if (::access(c.launcher.c_str(), X_OK) != 0) {
    throw UsageError("--launcher '" + c.launcher + "': no such program (retreat-launch)");
  }
}

std::vector<double> parse_lambdas(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) {
      throw UsageError("--lambdas '" + text + "': must be numbers separated by commas, e.g. 0.25,0.5,0.99");
    }
    out.push_back(v);
  }
  if (out.empty()) throw UsageError("--lambdas '" + text + "': give at least one density");
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"retreat-experiment: reproduces the paper's results (encounters, throughput, robotarium) and "
               "compares controllers, each into a run directory with data and report.html"};
  app.require_subcommand(1);

  EncountersOptions enc;
  std::uint64_t enc_seed = 0;
  std::uint32_t enc_robots = 0;
  double enc_duration = 0.0;
  auto* enc_cmd = app.add_subcommand("encounters", "inter-encounter and resolution times, fitted ρ (λ = 0.99, "
                                                   "δ = 0.11, v = 1)");
  add_common(enc_cmd, enc.common);
  auto* enc_seed_opt = enc_cmd->add_option("--seed", enc_seed, "world seed (default: the scenario's)");
  auto* enc_robots_opt = enc_cmd->add_option("--robots", enc_robots, "robots, at the scenario's density (default 200, quick 60)");
  auto* enc_duration_opt = enc_cmd->add_option("--duration", enc_duration, "measured seconds (default 100, quick 20)");

  ThroughputOptions thr;
  std::string thr_seeds;
  std::uint32_t thr_robots = 0;
  double thr_duration = 0.0;
  std::string thr_lambdas;
  auto* thr_cmd = app.add_subcommand("throughput", "simulated T(λ)λ over a grid of λ against the CTMC curve");
  add_common(thr_cmd, thr.common);
  thr_cmd->add_option("--seeds", thr_seeds, "world seeds A:B, pooled at each density (default: the scenario's seed)");
  auto* thr_robots_opt = thr_cmd->add_option("--robots", thr_robots, "robots per density (default 200, quick 40)");
  auto* thr_duration_opt = thr_cmd->add_option("--duration", thr_duration, "measured seconds (default 2500, quick 500)");
  thr_cmd->add_option("--lambdas", thr_lambdas, "densities, comma-separated (default 0.25,0.5,0.75,0.99,1.5,2,3,4; "
                                                "quick 0.5,0.99,2; 0.99 is always added: ρ is fitted there)");

  RobotariumOptions rob;
  std::string rob_seeds, rob_process_seeds;
  int rob_domain = -1;
  double rob_duration = 0.0;
  auto* rob_cmd = app.add_subcommand("robotarium", "population against time over many seeds (processes, in-process, "
                                                   "endless queue, kinetic world)");
  add_common(rob_cmd, rob.common);
  rob_cmd->add_option("--seeds", rob_seeds, "in-process seeds A:B (default 1:100, quick 1:3)");
  rob_cmd->add_option("--process-seeds", rob_process_seeds, "seeds A:B with agent processes (default 1:5, quick 1:2)");
  rob_cmd->add_flag("--no-processes", rob.no_processes, "skip the set-up with agent processes");
  rob_cmd->add_option("--dds", rob.dds, "vendor of the agent processes: fastdds or cyclonedds (default fastdds)");
  auto* rob_domain_opt = rob_cmd->add_option("--domain", rob_domain, "DDS domain of the process runs (default: a free one)");
  auto* rob_duration_opt = rob_cmd->add_option("--process-duration", rob_duration,
                                               "simulated seconds of the process runs (default: the scenario's "
                                               "1200, quick 150)");

  ControllersOptions ctl;
  std::string ctl_seeds;
  auto* ctl_cmd = app.add_subcommand("controllers", "every registered controller against paper on the same seeds");
  add_common(ctl_cmd, ctl.common);
  ctl_cmd->add_option("--seeds", ctl_seeds, "seeds A:B (default 1:100, quick 1:3)");

  // CLI11 would say only "A subcommand is required" for a misspelt one: name it.
  const auto known = [&](const std::string& word) {
    for (const auto* sub : {enc_cmd, thr_cmd, rob_cmd, ctl_cmd}) {
      if (sub->get_name() == word) return true;
    }
    return false;
  };
  if (argc > 1 && argv[1][0] != '-' && !known(argv[1])) {
    retreat::scenario::report_error("retreat-experiment", std::string("'") + argv[1] +
                                                              "': no such subcommand (encounters, throughput, "
                                                              "robotarium or controllers)");
    return 2;
  }
  if (const auto code = retreat::scenario::parse_command_line(app, argc, argv, "retreat-experiment")) return *code;
  install_signal_handlers();
  try {
    if (enc_cmd->parsed()) {
      finish_common(enc.common, "encounters");
      if (enc_seed_opt->count() > 0) enc.seed = enc_seed;
      if (enc_robots_opt->count() > 0) enc.robots = enc_robots;
      if (enc_duration_opt->count() > 0) enc.duration = enc_duration;
      return run_encounters(enc);
    }
    if (thr_cmd->parsed()) {
      finish_common(thr.common, "throughput");
      if (!thr_seeds.empty()) thr.seeds = parse_seed_range(thr_seeds, "--seeds");
      if (thr_robots_opt->count() > 0) thr.robots = thr_robots;
      if (thr_duration_opt->count() > 0) thr.duration = thr_duration;
      if (!thr_lambdas.empty()) thr.lambdas = parse_lambdas(thr_lambdas);
      return run_throughput(thr);
    }
    if (rob_cmd->parsed()) {
      finish_common(rob.common, "robotarium");
      if (!rob_seeds.empty()) rob.seeds = parse_seed_range(rob_seeds, "--seeds");
      if (!rob_process_seeds.empty()) rob.process_seeds = parse_seed_range(rob_process_seeds, "--process-seeds");
      if (rob_domain_opt->count() > 0) {
        if (rob_domain < 0 || rob_domain > 232) {
          throw UsageError("--domain " + std::to_string(rob_domain) + ": must be an integer in 0..232");
        }
        rob.domain = rob_domain;
      }
      if (rob_duration_opt->count() > 0) rob.process_duration = rob_duration;
      require_launcher(rob.common);
      return run_robotarium(rob);
    }
    finish_common(ctl.common, "controllers");
    if (!ctl_seeds.empty()) ctl.seeds = parse_seed_range(ctl_seeds, "--seeds");
    require_launcher(ctl.common);
    return run_controllers(ctl);
  } catch (const Stopped& s) {
    std::fprintf(stderr, "retreat-experiment: stopped by signal %d\n", s.signo);
    return 128 + s.signo;
  } catch (const UsageError& e) {
    retreat::scenario::report_error("retreat-experiment", e.what());
    return 2;
  } catch (const retreat::scenario::ConfigError& e) {
    retreat::scenario::report_error("retreat-experiment", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-experiment: run failed: %s\n", e.what());
    return 1;
  }
}
