// The portability check (docs/conventions.md, "Determinism"): runs one golden case of
// tests/scenario/golden_hashes.json in this process, over the in-memory transport with the
// arena's and the agents' own code (launch::run_in_memory), and compares its trajectory hash
// with the recorded one. Built in the main (GCC, libstdc++) tree and in a Clang + libc++ tree
// that has no yaml-cpp: it reads the case's resolved scenario as JSON
// (tests/portability/scenarios/<case>.json, which the main tree's golden test checks against
// the YAML scenario). Same hash from both builds: no draw depends on the standard library.
//
// Usage: retreat_golden_run GOLDEN_HASHES.json SCENARIOS_DIR CASE
// Exit code 0 when the hash and the retreat count are the recorded ones, 1 when not, 2 on bad
// input; one line on stdout either way.

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "retreat/launch/in_memory_run.hpp"
#include "retreat/scenario/json.hpp"

int main(int argc, char** argv) {
  using namespace retreat;
  if (argc != 4) {
    std::fprintf(stderr, "usage: retreat_golden_run GOLDEN_HASHES.json SCENARIOS_DIR CASE\n");
    return 2;
  }
  const std::string hashes_path = argv[1], scenarios = argv[2], name = argv[3];
  nlohmann::json recorded;
  scenario::Scenario s;
  try {
    std::ifstream in(hashes_path);
    const auto golden = nlohmann::json::parse(in);
    for (const auto& c : golden.at("cases")) {
      if (c.at("name") == name) recorded = c;
    }
    if (recorded.is_null()) throw std::invalid_argument("no case '" + name + "' in " + hashes_path);
    s = scenario::load_json(scenarios + "/" + name + ".json");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat_golden_run: %s\n", e.what());
    return 2;
  }
  const auto run = launch::run_in_memory(s, nullptr, [] { return true; });
  const auto& hash = run.summary.trajectory_sha256;
  const bool same = hash == recorded.at("trajectory_sha256").get<std::string>();
  std::printf("%s: %s %s (recorded %s)\n", name.c_str(), hash.c_str(), same ? "equal" : "DIFFERS",
              recorded.at("trajectory_sha256").get<std::string>().c_str());
  return same ? 0 : 1;
}
