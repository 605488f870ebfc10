// libFuzzer target: the Cyclone DDS 0.10 receive path of one message type
// (docs/fuzzing.md). Cyclone's default serdata checks the 4-byte encapsulation header,
// normalizes the payload against the type's marshalling ops (dds_stream_normalize: bounds,
// byte order, boolean and enum values, sequence lengths) and reads it into a sample
// (dds_stream_read_sample). retreat::transport::decode_cyclonedds runs both through their
// exported ops-level functions (dds_stream_normalize_data, dds_stream_read), then retreat's
// to_plain; here wire::validate follows. The same decoder reads recordings (retreat-replay,
// retreat-diff). Built once per type: RETREAT_FUZZ_TYPE is the IDL struct name,
// RETREAT_FUZZ_PER_ROBOT is 1 for types sent on a per-robot topic.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>

#include "cyclonedds_convert.hpp"
#include "retreat/transport/cyclonedds.hpp"
#include "retreat/wire/validate.hpp"

#define RETREAT_CAT2(a, b) a##b
#define RETREAT_CAT(a, b) RETREAT_CAT2(a, b)

namespace {

namespace cy = retreat::transport::cyclonedds;
using Vendor = RETREAT_CAT(retreat_msg_, RETREAT_FUZZ_TYPE);

constexpr std::optional<retreat::wire::RobotId> topic_robot =
    RETREAT_FUZZ_PER_ROBOT ? std::optional<retreat::wire::RobotId>(3) : std::nullopt;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The adapter's own decoder (retreat::transport::decode_cyclonedds: the header check, a private
  // 8-byte aligned copy of the body, normalization, the read, to_plain, the sample freed).
  using Plain = decltype(cy::to_plain(std::declval<const Vendor&>()));
  const auto plain = retreat::transport::decode_cyclonedds(
      retreat::wire::KindOf<Plain>::value, std::as_bytes(std::span(data, size)));
  if (plain) (void)retreat::wire::validate(*plain, topic_robot);
  return 0;
}
