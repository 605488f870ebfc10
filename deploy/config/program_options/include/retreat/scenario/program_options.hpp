#pragma once
/// @file
/// The command line every retreat program shares: --scenario, --dds, --domain, --set,
/// --print-config; one-line errors and exit code 2 for bad input.

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include "retreat/scenario/scenario.hpp"
#include "retreat/transport/transport.hpp"

namespace retreat::scenario {

/// Prints "<program>: <message>" as one line on stderr.
void report_error(std::string_view program, std::string_view message);

/// Adds the integer option @p name to @p app, stored in @p target (a T or a std::optional<T>) only
/// when given: a decimal whole number in @p lo..@p hi. Anything else is refused as one line
/// "NAME 'TEXT': must be a whole number in LO..HI" (exit code 2). CLI11's own reading of an
/// integer takes "-1" for the largest unsigned value, "010" for 8 and "0x10" for 16, and
/// saturates a value past its type's range.
template <class T, class Target>
CLI::Option* add_whole_number(CLI::App& app, const std::string& name, Target& target, const std::string& description,
                              T lo, T hi) {
  static_assert(std::is_integral_v<T>);
  return app
      .add_option_function<std::string>(
          name,
          [&target, name, lo, hi](const std::string& text) {
            T value{};
            const char* first = text.data();
            const char* last = first + text.size();
            const auto [end, error] = std::from_chars(first, last, value);
            if (error != std::errc() || end != last || first == last || value < lo || value > hi) {
              throw CLI::ValidationError(name + " '" + text + "': must be a whole number in " + std::to_string(lo) +
                                         ".." + std::to_string(hi));
            }
            target = value;
          },
          description)
      ->type_name("INT");
}

struct CommonOptions {
  std::string scenario_path;
  std::string dds;  ///< empty: the scenario's dds.vendor
  int domain = -1;  ///< -1: the scenario's dds.domain
  std::vector<std::string> overrides;
  bool print_config = false;
};

/// Adds the shared options to `app`. With `positional_scenario` the scenario file is the first
/// positional argument (retreat-launch), otherwise `--scenario FILE` (required).
void add_common_options(CLI::App& app, CommonOptions& options, bool positional_scenario = false);

/// Parses the command line. Returns an exit code when the program should stop now: 0 after
/// --help, 2 after a usage error (reported as one line "<program>: <message>").
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv,
                                      std::string_view program);

/// Runs @p validate, the start-up checks of a program's command line; bad input
/// (std::invalid_argument, which ConfigError is) is reported as one line "<program>: <message>"
/// and gives exit code 2. Anything else thrown is a bug and goes on to the caller (each program's
/// `main` still reports it as one line; tests/fuzz/command_line_fuzzer.cpp fails on it).
template <class Validate>
auto guarded(std::string_view program, Validate&& validate) -> decltype(validate()) {
  using Result = decltype(validate());
  try {
    return validate();
  } catch (const std::invalid_argument& e) {
    report_error(program, e.what());
    return Result(2);
  }
}

/// Runs a program's command-line parser from its `main`: a parser reports bad input itself (see
/// guarded); anything else it throws is a bug, still reported as one line with exit code 2,
/// never an abort.
template <class Parse>
auto parse_or_report(std::string_view program, Parse&& parse) -> decltype(parse()) {
  using Result = decltype(parse());
  try {
    return parse();
  } catch (const std::exception& e) {
    report_error(program, e.what());
    return Result(2);
  }
}

/// Seeds A..B inclusive (`--seeds A:B`).
struct SeedRange {
  std::uint64_t first = 1;
  std::uint64_t last = 1;
  std::size_t count() const { return static_cast<std::size_t>(last - first + 1); }
  std::string text() const { return std::to_string(first) + ":" + std::to_string(last); }
};

/// Parses "A:B" (whole numbers, 0 <= A <= B, at most 100000 seeds). @throws ConfigError naming
/// @p option, the value and what is allowed.
SeedRange parse_seed_range(const std::string& text, const std::string& option = "--seeds");

/// The largest `--jobs` (seeds run at once in one process).
inline constexpr unsigned max_jobs = 256;

/// The default `--jobs` of work shared among threads in one process: the core count (at least 1).
unsigned core_count();

/// Checks `--jobs N`: 1 <= N <= max_jobs. @throws ConfigError naming the value and the range.
void check_jobs(unsigned jobs);

/// Loads the scenario with --set overrides, then --dds and --domain. Throws ConfigError.
Scenario load_scenario(const CommonOptions& options);

/// A participant of the scenario's swarm (its `dds` section: domain, profile, and with
/// `dds.security: on` the identity @p identity of `dds.security_dir`, e.g. `robot_3`, `arena`,
/// `bridge`), announcing itself as @p name with @p user_data, on every domain of the swarm
/// (`dds.domains`): the arena's, the bridge's, a recorder's.
transport::ParticipantOptions participant_options(const Scenario& s, std::string name,
                                                  std::string user_data,
                                                  const std::string& identity);

/// The participant of robot @p robot's agent or driver: the same, on the robot's own domain only
/// (wire::robot_domain).
transport::ParticipantOptions robot_participant_options(const Scenario& s, wire::RobotId robot, std::string name,
                                                        std::string user_data, const std::string& identity);

/// Makes SIGINT and SIGTERM request a stop (see stop_requested) instead of ending the process.
void install_stop_handlers();

/// Whether SIGINT or SIGTERM has arrived since install_stop_handlers().
bool stop_requested();

/// While it lives, a stop request (SIGINT or SIGTERM after install_stop_handlers()) also calls
/// @p wake, once, from a thread of its own; at once if the stop was requested already. For a
/// loop that blocks until its next event (e.g. Transport::wait, with Transport::wake as @p wake)
/// instead of waking up to poll stop_requested(): a thousand idle agents polling ten times a
/// second cost a 2-core host more than their swarm's work. @p wake must be safe to call from
/// another thread; the destructor waits until a call in progress has returned.
class StopWakeup {
 public:
  explicit StopWakeup(std::function<void()> wake);
  ~StopWakeup();
  StopWakeup(const StopWakeup&) = delete;
  StopWakeup& operator=(const StopWakeup&) = delete;

 private:
  std::uint64_t id_;
};

/// How long a program whose work is done and recorded may take to tear down (delete its DDS
/// participant): Fast DDS 2.9 was once seen blocked for good in that, with peers still alive.
inline constexpr std::chrono::seconds teardown_limit{10};

/// Bounds the teardown of a program whose work is done and recorded: if the process is still
/// alive @p limit after this call (a DDS participant that does not finish deleting itself, say),
/// prints one line on stderr and ends the process at once with @p code. A process that exits in
/// time is not affected. Call it once, after the last output that matters has been written.
void limit_teardown(std::string_view program, std::chrono::seconds limit, int code);

}  // namespace retreat::scenario
