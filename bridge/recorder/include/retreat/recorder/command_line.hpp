#pragma once
/// @file
/// The command line of `retreat-record`, parsed and validated without joining DDS or writing a
/// file, so that the program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <string>
#include <variant>

#include "retreat/scenario/scenario.hpp"

namespace retreat::recorder {

struct RecordCommandLine {
  scenario::Scenario scenario;  ///< resolved and validated; a DDS vendor, no DDS Security
  std::string out;              ///< --out: the MCAP file to write
  bool print_config = false;
};

/// Parses `retreat-record`'s arguments and loads its scenario. Returns the options, or the exit
/// code to end with now: 0 after --help, 2 after bad input (reported as one line on stderr).
/// Creates nothing (an --out the program cannot create is refused when it opens the file).
std::variant<RecordCommandLine, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::recorder
