#pragma once
/// @file
/// The command line of `retreat-bridge`, parsed and validated without starting anything or
/// writing a file, so that the program and tests/fuzz/command_line_fuzzer.cpp run the same code.

#include <string>
#include <variant>

#include "retreat/bridge/address.hpp"
#include "retreat/scenario/scenario.hpp"

namespace retreat::bridge {

struct BridgeCommandLine {
  std::string report_dir;  ///< --report DIR: write DIR/report.html and exit (nothing else is read)
  scenario::Scenario scenario;  ///< resolved and validated (without --report)
  HttpAddress address;          ///< --http, else bridge.http
  std::string address_origin;   ///< which of the two gave `address`, for messages
  std::string out_dir;          ///< --out: record into this run directory (empty: none)
  std::string replay;           ///< --replay FILE: serve a recording's run, no DDS (empty: live)
  bool print_config = false;
};

/// Parses `retreat-bridge`'s arguments and loads its scenario. Returns the options, or the exit
/// code to end with now: 0 after --help, 2 after bad input (reported as one line on stderr).
/// Never throws std::invalid_argument; creates nothing.
std::variant<BridgeCommandLine, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::bridge
