#pragma once
// The generated PubSubType of a message, made safe to decode untrusted bytes.
//
// fastddsgen's deserialize() catches only NotEnoughMemoryException; a malformed sample (a
// non-zero first encapsulation octet, a boolean octet other than 0 or 1, ...) makes Fast CDR
// throw BadParamException, which would leave take_next_sample() and unwind through the
// middleware's listener thread. Here every Fast CDR exception becomes `false`, which Fast DDS
// treats as an undecodable sample and skips. Found by idl/fastdds/fuzz/decode_fuzzer.cpp.

#include <fastcdr/exceptions/Exception.h>
#include <fastdds/rtps/common/SerializedPayload.h>

namespace retreat::transport::fastdds {

template <class Generated>
class SafeTypeSupport final : public Generated {
 public:
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return Generated::deserialize(payload, data);
    } catch (const eprosima::fastcdr::exception::Exception&) {
      return false;
    }
  }
};

}  // namespace retreat::transport::fastdds
