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
  std::string tls_cert;         ///< --tls-cert FILE (with --tls-key): serve HTTPS
  std::string tls_key;          ///< --tls-key FILE
  std::string token;            ///< read from --token-file: every request must carry it (empty: none)
  bool print_config = false;
};

/// Whether @p host (an IPv4 address or `localhost`) is this machine's loopback: 127.0.0.0/8.
bool is_loopback(const std::string& host);

/// The bearer token in the file @p path: its text without the trailing line break.
/// @throws std::invalid_argument with one line naming the file when it cannot be read, or the
/// token is not 16 to 4,096 characters of A-Z a-z 0-9 - . _ ~ + / (RFC 6750's token68, no '=').
std::string read_token_file(const std::string& path);

/// Parses `retreat-bridge`'s arguments and loads its scenario. Returns the options, or the exit
/// code to end with now: 0 after --help, 2 after bad input (reported as one line on stderr).
/// Never throws std::invalid_argument; creates nothing.
std::variant<BridgeCommandLine, int> parse_command_line(int argc, char** argv);

}  // namespace retreat::bridge
