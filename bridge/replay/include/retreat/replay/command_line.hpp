#pragma once
/// @file
/// The command lines of `retreat-replay` and `retreat-diff`, parsed and validated without
/// reading a recording or joining DDS, so that the programs and tests/fuzz/command_line_fuzzer.cpp
/// run the same code.

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "retreat/replay/replay.hpp"

namespace retreat::replay {

struct ReplayCommandLine {
  std::string recording;  ///< the MCAP file
  ReplayOptions options;
  std::string dds;        ///< fastdds, cyclonedds or inmemory; empty: the recording's vendor
  int domain = -1;        ///< -1: the recording's domain
  bool spawn_agents = true;  ///< false (--no-agents): the agents are already running
  double answer_timeout = 60.0;  ///< [s] wall time a robot's agent may take to answer a frame
  std::string report;     ///< --report FILE: the outcome as JSON
};

/// Parses `retreat-replay`'s arguments. Returns the options, or the exit code to end with now:
/// 0 after --help, 2 after bad input (reported as one line on stderr).
std::variant<ReplayCommandLine, int> parse_replay_command_line(int argc, char** argv);

struct DiffCommandLine {
  std::string a, b;  ///< run directories or recordings
};

/// Parses `retreat-diff`'s arguments (as parse_replay_command_line).
std::variant<DiffCommandLine, int> parse_diff_command_line(int argc, char** argv);

}  // namespace retreat::replay
