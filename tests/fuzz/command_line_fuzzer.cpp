// libFuzzer target: every program's command line (docs/fuzzing.md). The input is a program name
// on the first line (agent, arena, bridge, launch, experiment, record, replay, diff) and one argument per further line; the
// program's own parser (the one its `main` calls) runs on them, which loads and validates the
// scenario, profile paths and every value, but starts nothing and writes nothing. Any argument
// vector must end in options or in exit code 0 (--help) or 2 (one line on stderr); any
// exception or crash is a bug. Run from the source tree, so that seeds can name
// deploy/scenarios/*.yaml.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "retreat/agent/command_line.hpp"
#include "retreat/arena/command_line.hpp"
#include "retreat/bridge/command_line.hpp"
#include "retreat/experiment/command_line.hpp"
#include "retreat/launch/command_line.hpp"
#include "retreat/recorder/command_line.hpp"
#include "retreat/replay/command_line.hpp"

namespace {

/// The exit code a parser returned, or 1 where it returned options (which is fine too).
template <class Options>
int exit_code_of(const std::variant<Options, int>& parsed) {
  const auto* code = std::get_if<int>(&parsed);
  return code == nullptr ? 1 : *code;
}

int parse(std::string_view program, int argc, char** argv) {
  using namespace retreat;
  if (program == "agent") return exit_code_of(agent::parse_command_line(argc, argv));
  if (program == "arena") return exit_code_of(arena::parse_command_line(argc, argv));
  if (program == "bridge") return exit_code_of(bridge::parse_command_line(argc, argv));
  if (program == "launch")
    return exit_code_of(launch::parse_command_line(argc, argv, "/nonexistent"));
  if (program == "experiment") return exit_code_of(experiment::parse_command_line(argc, argv));
  if (program == "record") return exit_code_of(recorder::parse_command_line(argc, argv));
  if (program == "replay") return exit_code_of(replay::parse_replay_command_line(argc, argv));
  if (program == "diff") return exit_code_of(replay::parse_diff_command_line(argc, argv));
  return -1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> lines;
  for (std::size_t begin = 0; begin <= text.size();) {
    const auto end = std::min(text.find('\n', begin), text.size());
    lines.emplace_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  if (lines.size() > 64) return 0;  // an argument vector, not a file
  std::vector<char*> argv;
  for (auto& line : lines) argv.push_back(line.data());  // argv[0]: the program's name
  argv.push_back(nullptr);
  const int code = parse(lines.front(), static_cast<int>(lines.size()), argv.data());
  if (code != -1 && code != 0 && code != 1 && code != 2) std::abort();
  return 0;
}
