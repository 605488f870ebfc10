// Writes the seed corpora of the wire decoders (tests/fuzz/corpus/<type>/): representative
// samples of every message type as they appear in a Robotarium run, each encoded by both
// vendors' own serializers (Fast DDS little-endian, Cyclone DDS big-endian), so that every
// decoder starts from real encodings of both byte orders.
// Usage: retreat_fuzz_write_corpus <corpus dir>   (docs/fuzzing.md)

#include "write_corpus.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fastdds_convert.hpp"
#include "retreat_msgsPubSubTypes.h"

namespace {

namespace fs = std::filesystem;
namespace wire = retreat::wire;
namespace fd = retreat::transport::fastdds;

void write(const fs::path& file, const std::vector<unsigned char>& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

template <class PubSub, class Plain>
std::vector<unsigned char> fastdds_bytes(const Plain& plain) {
  PubSub type;
  auto vendor = fd::to_vendor(plain);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&vendor)());
  type.serialize(&vendor, &payload);
  return {payload.data, payload.data + payload.length};
}

template <class PubSub, class Plain>
void write_samples(const fs::path& root, std::string_view type, const std::vector<Plain>& samples) {
  const auto dir = root / type;
  fs::create_directories(dir);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto bytes = fastdds_bytes<PubSub>(samples[i]);
    write(dir / ("fastdds-le-" + std::to_string(i)), bytes);
    write(dir / ("cyclonedds-be-" + std::to_string(i)), cyclonedds_big_endian(type, bytes));
  }
}

wire::Poses poses(int robots) {
  wire::Poses p{0, 240, 4.8, {}, {{-0.4f, 0.1f}}, {{0.45f, -0.2f}}};
  for (int i = 0; i < robots; ++i) {
    p.robots.push_back({static_cast<wire::RobotId>(i), 0.05f * static_cast<float>(i), -0.3f, 1.5f,
                        i < 8 ? wire::Phase::inside : wire::Phase::waiting, i % 2 == 0});
  }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus dir>\n", argv[0]);
    return 2;
  }
  const fs::path root = argv[1];
  using namespace retreat::msg;
  write_samples<ProximityFramePubSubType>(
      root, "ProximityFrame",
      std::vector<wire::ProximityFrame>{{3, 0, 0.0, wire::Phase::waiting, false, 0},
                                        {3, 240, 4.8, wire::Phase::inside, true, 2},
                                        {3, 900, 18.0, wire::Phase::retreating, false, 0}});
  write_samples<DecisionPubSubType>(
      root, "Decision", std::vector<wire::Decision>{{3, 240, 4.8, false}, {3, 900, 18.0, true}});
  write_samples<AgentStatusPubSubType>(
      root, "AgentStatus",
      std::vector<wire::AgentStatus>{{3, 240, 4.8, true, false, 4, 5.2, 0.031, 0},
                                     {3, 900, 18.0, false, true, 9, 11.7, 0.42, 2}});
  write_samples<ArenaTelemetryPubSubType>(
      root, "ArenaTelemetry",
      std::vector<wire::ArenaTelemetry>{{0, 240, 4.8, 8, 4, 1, 0, 0, 10.6, 3, 2400.0},
                                        {0, 900, 18.0, 5, 0, 0, 7, 1, 6.6, 12, 1900.0}});
  write_samples<PosesPubSubType>(root, "Poses", std::vector<wire::Poses>{poses(0), poses(12)});
  return 0;
}
