#pragma once
/// @file
/// The command line of `retreat-launch`, resolved to a Plan without starting anything or
/// writing a file, so that the program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <string>
#include <variant>

#include "retreat/launch/options.hpp"

namespace retreat::launch {

struct LaunchCommandLine {
  Plan plan;  ///< everything validated (make_plan)
  bool print_config = false;
};

/// Parses `retreat-launch`'s arguments and makes its plan; `self_dir` is the directory of the
/// launcher's executable (where the other programs are looked for). Returns the plan, or the
/// exit code to end with now: 0 after --help, 2 after bad input (reported as one line on
/// stderr). Never throws std::invalid_argument; creates nothing.
std::variant<LaunchCommandLine, int> parse_command_line(int argc, char** argv,
                                                        const std::string& self_dir);

}  // namespace retreat::launch
