#include "retreat/experiment/command_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "retreat/core/paths.hpp"
#include "retreat/model/format_number.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::experiment {
namespace {

namespace fs = std::filesystem;
constexpr const char* program = "retreat-experiment";

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

/// --jobs on a subcommand whose in-process seeds retreat-launch runs (robotarium, controllers, noise, sweep).
void add_jobs(CLI::App* sub, Common& c) {
  scenario::add_whole_number(*sub, "--jobs", c.jobs,
                             "in-process seeds run at once, 1..256, passed to retreat-launch --jobs, and the "
                             "threads that read the runs and compute the predictions (default: the core count)",
                             1u, scenario::max_jobs);
}

/// The defaults of the common options; the scenarios directory must exist.
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
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::string value = model::format_number(out[i]);
    if (!(out[i] > 0.0 && out[i] <= 20.0)) {
      throw UsageError("--lambdas '" + text + "': " + value + ": each must be in (0, 20] robots/m²");
    }
    if (std::find(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(i), out[i]) != out.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw UsageError("--lambdas '" + text + "': " + value + " is named twice");
    }
  }
  return out;
}

/// The longest --duration or --process-duration [s]: 400 times the longest default (throughput's
/// 2,500 s), and bounded in memory: the encounter intervals of 10⁶ s of 200 robots, kept for the
/// fit, are about 2·10⁸ numbers (1.6 GB).
constexpr double max_seconds = 1e6;

/// A duration option's value, when given: finite, > 0 and at most max_seconds.
void require_seconds(const char* option, const std::optional<double>& seconds) {
  if (!seconds || (*seconds > 0.0 && *seconds <= max_seconds)) return;
  throw UsageError(std::string(option) + " " + model::format_number(*seconds) +
                   ": must be a number of seconds > 0 and <= " + model::format_number(max_seconds));
}

/// An option that keeps its default unless given: CLI11 parses into `raw`, `into` copies it.
template <class T>
struct Given {
  T raw{};
  CLI::Option* option = nullptr;
  void into(std::optional<T>& target) const {
    if (option->count() > 0) target = raw;
  }
};

/// `encounters`: the options, then their check.
struct EncountersLine {
  EncountersOptions o;
  Given<std::uint64_t> seed;
  Given<std::uint32_t> robots;
  Given<double> duration;
  CLI::App* sub = nullptr;

  void add(CLI::App& app) {
    sub = app.add_subcommand("encounters", "inter-encounter and resolution times, fitted ρ (λ = 0.99, "
                                           "δ = 0.11, v = 1)");
    add_common(sub, o.common);
    seed.option = scenario::add_whole_number(*sub, "--seed", seed.raw, "world seed (default: the scenario's)",
                                             std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max());
    robots.option = scenario::add_whole_number(*sub, "--robots", robots.raw,
                                               "robots, at the scenario's density (default 200, quick 60)",
                                               std::uint32_t{2}, std::numeric_limits<std::uint32_t>::max());
    duration.option = sub->add_option("--duration", duration.raw, "measured seconds (default 100, quick 20)");
  }
  EncountersOptions finish() {
    finish_common(o.common, "encounters");
    seed.into(o.seed);
    robots.into(o.robots);
    duration.into(o.duration);
    require_seconds("--duration", o.duration);
    return o;
  }
};

/// `throughput`: the options, then their check.
struct ThroughputLine {
  ThroughputOptions o;
  std::string seeds, lambdas;
  Given<std::uint32_t> robots;
  Given<double> duration;
  CLI::App* sub = nullptr;

  void add(CLI::App& app) {
    sub = app.add_subcommand("throughput", "simulated T(λ)λ over a grid of λ against the CTMC curve");
    add_common(sub, o.common);
    sub->add_option("--seeds", seeds, "world seeds A:B, pooled at each density (default: the scenario's seed)");
    robots.option = scenario::add_whole_number(*sub, "--robots", robots.raw, "robots per density (default 200, quick 40)",
                                               std::uint32_t{2}, std::numeric_limits<std::uint32_t>::max());
    duration.option = sub->add_option("--duration", duration.raw, "measured seconds (default 2500, quick 500)");
    sub->add_option("--lambdas", lambdas, "densities, comma-separated (default 0.25,0.5,0.75,0.99,1.5,2,3,4; "
                                          "quick 0.5,0.99,2; 0.99 is always added: ρ is fitted there)");
  }
  ThroughputOptions finish() {
    finish_common(o.common, "throughput");
    if (!seeds.empty()) o.seeds = parse_seed_range(seeds, "--seeds");
    robots.into(o.robots);
    duration.into(o.duration);
    if (!lambdas.empty()) o.lambdas = parse_lambdas(lambdas);
    require_seconds("--duration", o.duration);
    return o;
  }
};

/// `robotarium`: the options, then their check.
struct RobotariumLine {
  RobotariumOptions o;
  std::string seeds, process_seeds;
  Given<int> domain;
  Given<double> duration;
  CLI::App* sub = nullptr;

  void add(CLI::App& app) {
    sub = app.add_subcommand("robotarium", "population against time over many seeds (processes, in-process, "
                                           "endless queue, kinetic world)");
    add_common(sub, o.common);
    add_jobs(sub, o.common);
    sub->add_option("--seeds", seeds, "in-process seeds A:B (default 1:100, quick 1:3)");
    sub->add_option("--process-seeds", process_seeds, "seeds A:B with agent processes (default 1:5, quick 1:2)");
    sub->add_flag("--no-processes", o.no_processes, "skip the set-up with agent processes");
    sub->add_option("--dds", o.dds, "vendor of the agent processes: fastdds or cyclonedds (default fastdds)");
    domain.option = scenario::add_whole_number(*sub, "--domain", domain.raw,
                                               "DDS domain of the process runs (default: a free one)", 0,
                                               transport::max_domain_id);
    duration.option = sub->add_option("--process-duration", duration.raw,
                                      "simulated seconds of the process runs (default: the scenario's 1200, quick 150)");
  }
  RobotariumOptions finish() {
    finish_common(o.common, "robotarium");
    if (!seeds.empty()) o.seeds = parse_seed_range(seeds, "--seeds");
    if (!process_seeds.empty()) o.process_seeds = parse_seed_range(process_seeds, "--process-seeds");
    domain.into(o.domain);
    duration.into(o.process_duration);
    require_launcher(o.common);
    if (o.dds != "fastdds" && o.dds != "cyclonedds") {
      throw UsageError("--dds '" + o.dds + "': must be fastdds or cyclonedds");
    }
    require_seconds("--process-duration", o.process_duration);
    return o;
  }
};

/// A subcommand whose own options are --seeds and --controllers (controllers, noise, sweep): the options, then
/// their check. `Options` has `common` and `seeds`.
template <typename Options>
struct SeedsLine {
  SeedsLine(const char* name_, const char* description_, const char* seeds_help_)
      : name(name_), description(description_), seeds_help(seeds_help_) {}

  const char* name;
  const char* description;
  const char* seeds_help;
  Options o;
  std::string seeds;
  std::vector<std::string> controllers;
  CLI::App* sub = nullptr;

  void add(CLI::App& app) {
    sub = app.add_subcommand(name, description);
    add_common(sub, o.common);
    add_jobs(sub, o.common);
    sub->add_option("--seeds", seeds, seeds_help);
    sub->add_option("--controllers", controllers,
                    "registered rules to compare, comma-separated (default: every one; paper always runs, "
                    "as the reference)")
        ->delimiter(',');
    sub->add_option("--set", o.common.overrides,
                    "override a value of every run's scenario, section.key=value (repeatable; the subcommand's "
                    "own values, e.g. a sweep's cell, come after it), e.g. arena.retreat_unblock=true");
  }
  Options finish() {
    finish_common(o.common, name);
    if (!seeds.empty()) o.seeds = parse_seed_range(seeds, "--seeds");
    check_controllers(controllers);
    o.common.controllers = controllers;
    // Each must make both queues' scenarios valid, as the launcher will check: refused here.
    for (const auto& c : queue_cases(o.common)) {
      try {
        scenario::load(c.file, o.common.overrides);
      } catch (const scenario::ConfigError& e) {
        throw UsageError(std::string("--set: ") + e.what());
      }
    }
    require_launcher(o.common);
    return o;
  }
};

}  // namespace

std::variant<ExperimentCommand, int> parse_command_line(int argc, char** argv) {
  CLI::App app{"retreat-experiment: reproduces the paper's results (encounters, throughput, robotarium) and "
               "compares controllers, each into a run directory with data and report.html"};
  app.require_subcommand(1);
  EncountersLine encounters;
  ThroughputLine throughput;
  RobotariumLine robotarium;
  SeedsLine<ControllersOptions> controllers{"controllers", "every registered controller against paper on the same seeds",
                                            "seeds A:B (default 1:100, quick 1:3)"};
  SeedsLine<NoiseOptions> noise{"noise", "every registered controller with missed and false onsets",
                                "seeds A:B (default 1:100, quick 1:2)"};
  SeedsLine<SweepOptions> sweep{"sweep", "every registered controller on a grid of scenarios",
                                "seeds A:B (default 1:100, quick 1:2)"};
  encounters.add(app);
  throughput.add(app);
  robotarium.add(app);
  controllers.add(app);
  noise.add(app);
  sweep.add(app);
  // CLI11 would say only "A subcommand is required" for a misspelt one: name it.
  const auto known = [&](const std::string& word) {
    for (const auto* sub : {encounters.sub, throughput.sub, robotarium.sub, controllers.sub, noise.sub, sweep.sub}) {
      if (sub->get_name() == word) return true;
    }
    return false;
  };
  if (argc > 1 && argv[1][0] != '-' && !known(argv[1])) {
    scenario::report_error(program, std::string("'") + argv[1] +
                                        "': no such subcommand (encounters, throughput, robotarium, controllers, noise or sweep)");
    return 2;
  }
  if (const auto code = scenario::parse_command_line(app, argc, argv, program)) return *code;
  return scenario::guarded(program, [&]() -> std::variant<ExperimentCommand, int> {
    if (encounters.sub->parsed()) return ExperimentCommand{encounters.finish()};
    if (throughput.sub->parsed()) return ExperimentCommand{throughput.finish()};
    if (robotarium.sub->parsed()) return ExperimentCommand{robotarium.finish()};
    if (noise.sub->parsed()) return ExperimentCommand{noise.finish()};
    if (sweep.sub->parsed()) return ExperimentCommand{sweep.finish()};
    return ExperimentCommand{controllers.finish()};
  });
}

}  // namespace retreat::experiment
