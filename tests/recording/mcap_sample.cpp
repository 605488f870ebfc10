// Writes the MCAP file that read_mcap.mjs checks with the reference reader (@mcap/core): a
// known sequence of messages on three channels, in many chunks, with metadata.
//
//   retreat_mcap_sample FILE zstd|none CHUNK_BYTES MESSAGES
//
// Message i (0-based) is on channel i % 3, with sequence i, log time 1,000,000·i + 7 ns and
// publish time 3 ns earlier. Channels 0 ("/frames") and 1 ("/decisions") carry the CDR bytes of
// the schema's struct {uint32 robot = i; double value = i / 2} (little-endian encapsulation);
// channel 2 ("/log") carries the JSON text {"i":i} and has no schema.

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "retreat/recording/mcap_writer.hpp"

namespace {

std::vector<std::byte> cdr_sample(std::uint32_t robot, double value) {
  std::vector<std::byte> out = {std::byte{0x00}, std::byte{0x01}, std::byte{0x00},
                                std::byte{0x00}};  // CDR_LE
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<std::byte>((robot >> (8 * b)) & 0xFF));
  out.resize(out.size() +
             4);  // the double is aligned to 8 from the end of the encapsulation header
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<std::byte>((bits >> (8 * b)) & 0xFF));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s FILE zstd|none CHUNK_BYTES MESSAGES\n", argv[0]);
    return 2;
  }
  try {
    retreat::recording::McapOptions options;
    options.compression = std::string(argv[2]) == "zstd" ? retreat::recording::Compression::zstd
                                                         : retreat::recording::Compression::none;
    options.chunk_size = std::stoul(argv[3]);
    const std::uint32_t messages = static_cast<std::uint32_t>(std::stoul(argv[4]));
    retreat::recording::McapWriter mcap(argv[1], options);
    mcap.add_metadata("retreat", {{"scenario", "robotarium-2019"}, {"seed", "1"}});
    const auto schema = mcap.add_schema("retreat::msg::Sample", "omgidl",
                                        "module retreat { module msg {\n"
                                        "  struct Sample { uint32 robot; double value; };\n"
                                        "}; };\n");
    const std::array channels = {mcap.add_channel(schema, "/frames", "cdr", {{"vendor", "test"}}),
                                 mcap.add_channel(schema, "/decisions", "cdr"),
                                 mcap.add_channel(0, "/log", "json")};
    for (std::uint32_t i = 0; i < messages; ++i) {
      const auto channel = channels[i % 3];
      const std::uint64_t log_time = 1'000'000ULL * i + 7;
      if (i % 3 == 2) {
        const std::string json = "{\"i\":" + std::to_string(i) + "}";
        mcap.write(channel, i, log_time, log_time - 3,
                   std::as_bytes(std::span(json.data(), json.size())));
      } else {
        mcap.write(channel, i, log_time, log_time - 3, cdr_sample(i, i / 2.0));
      }
    }
    mcap.add_metadata("end", {{"messages", std::to_string(messages)}});
    mcap.close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "retreat_mcap_sample: %s\n", e.what());
    return 1;
  }
  return 0;
}
