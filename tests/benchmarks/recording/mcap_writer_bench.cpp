// How fast retreat::recording::McapWriter takes messages: proximity-frame-sized CDR payloads
// (48 bytes) on 16 channels into a file in the system's temporary directory, zstd or
// uncompressed chunks of 1 MiB, closed (summary written) at the end of each batch. Reported as
// messages per second; the file is removed after each run.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "retreat/recording/mcap_writer.hpp"

namespace {

void write_batch(benchmark::State& state, retreat::recording::Compression compression) {
  const auto path =
      (std::filesystem::temp_directory_path() / "retreat_mcap_writer_bench.mcap").string();
  const std::int64_t batch = state.range(0);
  std::vector<std::byte> payload(48);
  for (std::size_t i = 0; i < payload.size(); ++i)
    payload[i] = static_cast<std::byte>(i * 37 % 251);
  std::uint64_t bytes = 0;
  for (auto _ : state) {
    retreat::recording::McapOptions options;
    options.compression = compression;
    retreat::recording::McapWriter mcap(path, options);
    const auto schema =
        mcap.add_schema("retreat::msg::ProximityFrame", "omgidl", "struct ProximityFrame {};");
    std::vector<std::uint16_t> channels;
    for (int c = 0; c < 16; ++c)
      channels.push_back(mcap.add_channel(schema, "/robot_" + std::to_string(c), "cdr"));
    for (std::int64_t i = 0; i < batch; ++i) {
      payload[4] = static_cast<std::byte>(i & 0xFF);  // the tick changes, as in a run
      const auto t = static_cast<std::uint64_t>(i) * 30'000'000ULL / 16;
      mcap.write(channels[static_cast<std::size_t>(i % 16)], static_cast<std::uint32_t>(i), t, t,
                 payload);
    }
    mcap.close();
    bytes = std::filesystem::file_size(path);
  }
  std::filesystem::remove(path);
  state.SetItemsProcessed(state.iterations() * batch);
  state.counters["file_bytes_per_message"] =
      static_cast<double>(bytes) / static_cast<double>(batch);
}

void BM_McapWriteZstd(benchmark::State& state) {
  write_batch(state, retreat::recording::Compression::zstd);
}
void BM_McapWriteUncompressed(benchmark::State& state) {
  write_batch(state, retreat::recording::Compression::none);
}

}  // namespace

BENCHMARK(BM_McapWriteZstd)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_McapWriteUncompressed)->Arg(1'000'000)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
