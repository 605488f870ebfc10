#pragma once
// The Cyclone DDS half of write_corpus (its own translation unit: both code generators name
// their header retreat_msgs.h).

#include <string_view>
#include <vector>

/// The same sample re-encoded by Cyclone DDS as big-endian XCDR1: `cdr` (a little-endian XCDR1
/// sample with its encapsulation header) is read with Cyclone's deserializer and written again
/// with its serializer. `type` is the IDL struct name, e.g. "Poses".
std::vector<unsigned char> cyclonedds_big_endian(std::string_view type,
                                                 const std::vector<unsigned char>& cdr);
