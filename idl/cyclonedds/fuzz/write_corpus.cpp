#include "write_corpus.hpp"

#include <dds/ddsi/ddsi_cdrstream.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "retreat_msgs.h"

namespace {

const dds_topic_descriptor_t& descriptor(std::string_view type) {
  if (type == "ProximityFrame") return retreat_msg_ProximityFrame_desc;
  if (type == "Decision") return retreat_msg_Decision_desc;
  if (type == "AgentStatus") return retreat_msg_AgentStatus_desc;
  if (type == "ArenaTelemetry") return retreat_msg_ArenaTelemetry_desc;
  if (type == "Poses") return retreat_msg_Poses_desc;
  throw std::invalid_argument("no such type: " + std::string(type));
}

}  // namespace

std::vector<unsigned char> cyclonedds_big_endian(std::string_view type,
                                                 const std::vector<unsigned char>& cdr) {
  const auto& desc = descriptor(type);
  if (cdr.size() < 4 || cdr[1] != 0x01) throw std::invalid_argument("not little-endian XCDR1");
  std::vector<unsigned char> body(cdr.begin() + 4, cdr.end());
  const auto size = static_cast<std::uint32_t>(body.size());
  std::uint32_t offset = 0;
  const bool bswap = DDSRT_ENDIAN != DDSRT_LITTLE_ENDIAN;
  if (dds_stream_normalize_data(reinterpret_cast<char*>(body.data()), &offset, size, bswap, 1,
                                desc.m_ops) == nullptr) {
    throw std::invalid_argument("Cyclone DDS rejects the sample");
  }
  void* sample = std::calloc(1, desc.m_size);
  dds_istream_t in;
  dds_istream_init(&in, size, body.data(), 1);
  dds_stream_read(&in, static_cast<char*>(sample), desc.m_ops);
  dds_istream_fini(&in);

  dds_ostream_t out;
  dds_ostream_init(&out, 0, 1);
  (void)dds_stream_write_with_byte_order(&out, static_cast<const char*>(sample), desc.m_ops,
                                         DDSRT_BOSEL_BE);
  std::vector<unsigned char> bytes{0x00, 0x00, 0x00, 0x00};  // CDR_BE, no options
  bytes.insert(bytes.end(), out.m_buffer, out.m_buffer + out.m_index);
  dds_ostream_fini(&out);
  dds_stream_free_sample(sample, desc.m_ops);
  std::free(sample);
  return bytes;
}
