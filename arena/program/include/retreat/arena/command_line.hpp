#pragma once
/// @file
/// The command line of `retreat-arena`, parsed and validated without starting anything or
/// writing a file, so that the program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <string>
#include <variant>

#include "retreat/scenario/scenario.hpp"

namespace retreat::arena {

struct ArenaCommandLine {
  scenario::Scenario scenario;  ///< resolved and validated, with --set, --dds and --domain
  std::string out_dir;          ///< --out: the run directory (empty: none)
  bool resume = false;          ///< --resume: continue the run in out_dir (never without it)
  bool print_config = false;
};

/// Parses `retreat-arena`'s arguments and loads its scenario. Returns the options, or the exit
/// code to end with now: 0 after --help, 2 after bad input (reported as one line on stderr).
/// Never throws std::invalid_argument; creates nothing.
std::variant<ArenaCommandLine, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::arena
