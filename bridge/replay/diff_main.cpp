// retreat-diff A B: where two runs diverge (docs/recording.md, "Diff"). A and B are two run
// directories (their hash chains, transitions and telemetry) or two recordings (message by
// message). Prints "identical: ..." or "differ at tick K: robot R FIELD A x, B y" and details;
// exit codes as diff(1): 0 identical, 1 they differ, 2 bad input (one line).

#include <iostream>

#include "retreat/replay/command_line.hpp"
#include "retreat/replay/diff.hpp"
#include "retreat/scenario/program_options.hpp"

int main(int argc, char** argv) {
  using namespace retreat;
  constexpr const char* program = "retreat-diff";
  const auto parsed = scenario::parse_or_report(program, [&] { return replay::parse_diff_command_line(argc, argv); });
  if (const auto* code = std::get_if<int>(&parsed)) return *code;
  const auto& cl = std::get<replay::DiffCommandLine>(parsed);
  try {
    const auto result = replay::diff_runs(cl.a, cl.b);
    std::cout << result.report << std::flush;
    return result.identical ? 0 : 1;
  } catch (const replay::DiffError& e) {
    scenario::report_error(program, e.what());
    return 2;
  } catch (const std::exception& e) {
    scenario::report_error(program, e.what());
    return 2;
  }
}
