// libFuzzer target: an agent's frame journal (retreat-agent --journal, docs/protocol.md §6,
// "A restarted agent"). Any file either opens, giving only valid frames, or is refused with
// std::invalid_argument (the agent prints it as one line and exits 2); any other exception or
// crash is a bug. A journal that opens takes one more frame, and opened again gives back exactly
// what it gave plus that frame.

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "retreat/agent/frame_journal.hpp"

namespace {

const std::string header = "# retreat-agent journal 1 robot=3 fingerprint=0";

bool valid(const retreat::wire::ProximityFrame& f) {
  return f.robot_id == 3 && f.tick >= 0 && std::isfinite(f.time) && f.time >= 0.0 &&
         static_cast<unsigned>(f.phase) < retreat::wire::phase_count;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("retreat_journal_fuzz_" + std::to_string(::getpid()))).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 static_cast<std::streamsize>(size));
  std::vector<retreat::wire::ProximityFrame> first;
  const retreat::wire::ProximityFrame extra{3, 1'000'000, 12345.678901234567, retreat::wire::Phase::inside, true, 2};
  try {
    retreat::agent::FrameJournal journal(path, header, 3);
    first = journal.recovered();
    for (const auto& f : first) {
      if (!valid(f)) std::abort();
    }
    if (!journal.append(extra)) std::abort();
  } catch (const std::invalid_argument&) {
    std::filesystem::remove(path);
    return 0;
  }
  retreat::agent::FrameJournal again(path, header, 3);  // must open: it is what the agent wrote to
  const auto& second = again.recovered();
  if (second.size() != first.size() + 1 || second.back() != extra) std::abort();
  for (std::size_t i = 0; i < first.size(); ++i) {
    if (!(second[i] == first[i])) std::abort();
  }
  std::filesystem::remove(path);
  return 0;
}
