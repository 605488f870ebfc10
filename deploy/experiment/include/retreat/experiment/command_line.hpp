#pragma once
/// @file
/// The command line of `retreat-experiment`, parsed and validated without running anything or
/// creating a file or directory (the run directory is made by the subcommand), so that the
/// program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <variant>

#include "retreat/experiment/subcommands.hpp"

namespace retreat::experiment {

/// One subcommand and its options, every default resolved (--out, --scenarios, --launcher) and
/// every value checked.
struct ExperimentCommand {
  std::variant<EncountersOptions, ThroughputOptions, RobotariumOptions, ControllersOptions, NoiseOptions, SweepOptions>
      options;
};

/// Parses `retreat-experiment`'s arguments. Returns the subcommand, or the exit code to end with
/// now: 0 after --help, 2 after bad input (reported as one line on stderr). Never throws
/// std::invalid_argument; creates nothing.
std::variant<ExperimentCommand, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::experiment
