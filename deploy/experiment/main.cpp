// retreat-experiment: reproduces the paper's results and compares controllers, one subcommand
// each, every one writing a run directory with its data (CSV, JSON) and report.html (figures,
// self-contained):
//   encounters   inter-encounter and encounter-resolution times, fitted ρ (MODEL.md §2, §6)
//   throughput   simulated T(λ)λ over a grid of λ against the CTMC curve (MODEL.md §3)
//   robotarium   population against time over many seeds (agent processes, in-process, endless
//                queue, kinetic world), run by retreat-launch
//   controllers  every registered controller against paper on the same seeds (J of MODEL.md §4)
//   noise        every registered controller with missed and false onsets (sensing noise)
//   sweep        every registered controller on a grid of 18 scenarios
// Reads the shipped scenarios (--scenarios DIR); runs retreat-launch (beside this program, or
// --launcher) as a child process. No DDS of its own: the launcher and its children use DDS in
// `robotarium`'s process set-up only.
//
// Exit codes: 0 done; 1 a run failed; 2 bad input (nothing was started); 128 + signal when
// SIGINT/SIGTERM/SIGHUP stopped it (the launcher is stopped first).

#include <csignal>
#include <cstdio>
#include <type_traits>
#include <variant>

#include "retreat/experiment/command_line.hpp"
#include "launch.hpp"
#include "retreat/scenario/program_options.hpp"
#include "retreat/scenario/scenario.hpp"

namespace {

using namespace retreat::experiment;
constexpr const char* program = "retreat-experiment";

extern "C" void on_signal(int signo) { stop_signal.store(signo); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &sa, nullptr);
}

/// Runs the subcommand, and turns what it throws into the exit code (see the top of this file).
int run_reported(const ExperimentCommand& command) {
  try {
    return std::visit(
        [](const auto& o) {
          using Options = std::decay_t<decltype(o)>;
          if constexpr (std::is_same_v<Options, EncountersOptions>) return run_encounters(o);
          if constexpr (std::is_same_v<Options, ThroughputOptions>) return run_throughput(o);
          if constexpr (std::is_same_v<Options, RobotariumOptions>) return run_robotarium(o);
          if constexpr (std::is_same_v<Options, ControllersOptions>) return run_controllers(o);
          if constexpr (std::is_same_v<Options, NoiseOptions>) return run_noise(o);
          if constexpr (std::is_same_v<Options, SweepOptions>) return run_sweep(o);
        },
        command.options);
  } catch (const Stopped& s) {
    std::fprintf(stderr, "retreat-experiment: stopped by signal %d\n", s.signo);
    return 128 + s.signo;
  } catch (const UsageError& e) {
    retreat::scenario::report_error(program, e.what());
    return 2;
  } catch (const retreat::scenario::ConfigError& e) {
    retreat::scenario::report_error(program, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat-experiment: run failed: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const auto parsed = retreat::scenario::parse_or_report(program, [&] { return parse_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  install_signal_handlers();
  return run_reported(std::get<ExperimentCommand>(parsed));
}
