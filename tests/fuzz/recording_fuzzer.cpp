// libFuzzer target: every tool that reads a recording (retreat-replay, retreat-diff) starts with
// retreat::replay::parse_recording: the MCAP reader (records, chunks, zstd, CRCs), the run's
// metadata and scenario (JSON), and each message decoded with a DDS vendor's generated code and
// validated. Any input must give a Recording or a RecordingError, nothing else (docs/fuzzing.md).

#include <cstddef>
#include <cstdint>
#include <span>

#include "retreat/replay/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto recording =
        retreat::replay::parse_recording(std::as_bytes(std::span(data, size)), "fuzz.mcap");
    (void)recording;
  } catch (const retreat::replay::RecordingError&) {
    // refused in one line: what it should do
  }
  return 0;
}
