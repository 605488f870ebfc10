// libFuzzer target: the Fast DDS receive path of one message type, exactly as
// retreat::transport::fastdds decodes a sample (docs/fuzzing.md):
//   serialized bytes -> SafeTypeSupport<generated PubSubType>::deserialize -> to_plain ->
//   wire::validate.
// A sample that decodes must survive a round trip: to_vendor -> serialize -> deserialize
// -> to_plain gives the same bytes again. Built once per type: RETREAT_FUZZ_TYPE is the IDL
// struct name, RETREAT_FUZZ_PER_ROBOT is 1 for types sent on a per-robot topic.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <vector>

#include "fastdds_convert.hpp"
#include "fastdds_type_support.hpp"
#include "retreat/wire/validate.hpp"
#include "retreat_msgsPubSubTypes.h"

#define RETREAT_CAT2(a, b) a##b
#define RETREAT_CAT(a, b) RETREAT_CAT2(a, b)

namespace {

namespace fd = retreat::transport::fastdds;
using eprosima::fastrtps::rtps::SerializedPayload_t;
using Vendor = retreat::msg::RETREAT_FUZZ_TYPE;
using Type = fd::SafeTypeSupport<retreat::msg::RETREAT_CAT(RETREAT_FUZZ_TYPE, PubSubType)>;

/// The robot whose per-robot topic the sample arrives on (as in Reader::take()).
constexpr std::optional<retreat::wire::RobotId> topic_robot =
    RETREAT_FUZZ_PER_ROBOT ? std::optional<retreat::wire::RobotId>(3) : std::nullopt;

std::vector<unsigned char> serialize(Type& type, const Vendor& sample) {
  SerializedPayload_t payload(type.getSerializedSizeProvider(const_cast<Vendor*>(&sample))());
  if (!type.serialize(const_cast<Vendor*>(&sample), &payload)) std::abort();
  return {payload.data, payload.data + payload.length};
}

bool deserialize(Type& type, const unsigned char* data, std::size_t size, Vendor& out) {
  SerializedPayload_t payload(static_cast<std::uint32_t>(size));
  if (size > 0) std::memcpy(payload.data, data, size);
  payload.length = static_cast<std::uint32_t>(size);
  return type.deserialize(&payload, &out);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Type type;
  Vendor sample;
  if (!deserialize(type, data, size, sample)) return 0;
  const auto plain = fd::to_plain(sample);
  (void)retreat::wire::validate(retreat::wire::AnyMessage{plain}, topic_robot);

  // Round trip through the writer's conversion: compare bytes, not values (NaN != NaN).
  const auto bytes = serialize(type, fd::to_vendor(plain));
  Vendor again;
  if (!deserialize(type, bytes.data(), bytes.size(), again)) std::abort();
  if (serialize(type, fd::to_vendor(fd::to_plain(again))) != bytes) std::abort();
  return 0;
}
