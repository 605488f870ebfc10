#pragma once
/// @file
/// The command line of `retreat-agent`, parsed and validated without starting anything, so that
/// the program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <cstdint>
#include <string>
#include <variant>

#include "retreat/scenario/scenario.hpp"

namespace retreat::agent {

struct AgentCommandLine {
  scenario::Scenario scenario;  ///< resolved and validated, with --set, --dds and --domain
  std::uint32_t robot_id = 0;   ///< --robot-id, a robot the scenario has
  std::string journal;          ///< --journal FILE: journal accepted frames, resume from them
  bool print_config = false;
};

/// Parses `retreat-agent`'s arguments and loads its scenario. Returns the options, or the exit
/// code to end with now: 0 after --help, 2 after bad input (reported as one line on stderr).
/// Never throws for any argument vector.
std::variant<AgentCommandLine, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::agent
