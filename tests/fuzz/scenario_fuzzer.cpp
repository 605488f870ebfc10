// libFuzzer target: the scenario loader (docs/fuzzing.md). Any text either loads or is
// refused with a ConfigError (which every program prints as one line and exits 2); any other
// exception or crash is a bug. A scenario that loads must dump to YAML that loads again to the
// same dump (scenario.hpp: "loading it again gives the same Scenario").

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "retreat/scenario/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  retreat::scenario::Scenario s;
  try {
    s = retreat::scenario::parse(text, {}, "fuzz.yaml");
  } catch (const retreat::scenario::ConfigError&) {
    return 0;
  }
  const std::string dumped = retreat::scenario::dump(s);
  if (retreat::scenario::dump(retreat::scenario::parse(dumped, {}, "dump.yaml")) != dumped) {
    std::abort();
  }
  return 0;
}
