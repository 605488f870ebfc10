#include "retreat/transport/factory.hpp"

#include <stdexcept>

#include "retreat/transport/inmemory.hpp"
#include "retreat/transport/sharded.hpp"
#ifdef RETREAT_HAVE_FASTDDS
#include "retreat/transport/fastdds.hpp"
#endif
#ifdef RETREAT_HAVE_CYCLONEDDS
#include "retreat/transport/cyclonedds.hpp"
#endif

namespace retreat::transport {

std::vector<std::string> dds_vendors() {
  std::vector<std::string> out;
#ifdef RETREAT_HAVE_FASTDDS
  out.emplace_back("fastdds");
#endif
#ifdef RETREAT_HAVE_CYCLONEDDS
  out.emplace_back("cyclonedds");
#endif
  return out;
}

std::vector<std::string> available_vendors() {
  auto out = dds_vendors();
  out.emplace_back("inmemory");
  return out;
}

namespace {

std::unique_ptr<Transport> make_one_domain(std::string_view vendor, const ParticipantOptions& options) {
#ifdef RETREAT_HAVE_FASTDDS
  if (vendor == "fastdds") return make_fastdds_transport(options);
#endif
#ifdef RETREAT_HAVE_CYCLONEDDS
  if (vendor == "cyclonedds") return make_cyclonedds_transport(options);
#endif
  if (vendor == "inmemory") return make_inmemory_transport(inmemory_bus_for_domain(options.domain_id), options);
  std::string allowed;
  for (const auto& v : available_vendors()) allowed += (allowed.empty() ? "" : ", ") + v;
  throw std::invalid_argument("--dds '" + std::string(vendor) + "': must be one of " + allowed);
}

}  // namespace

std::unique_ptr<Transport> make_transport(std::string_view vendor, const ParticipantOptions& options) {
  if (options.domains == 1) return make_one_domain(vendor, options);
  validate(options);
  std::vector<std::unique_ptr<Transport>> shards;
  for (int i = 0; i < options.domains; ++i) {
    ParticipantOptions one = options;
    one.domain_id = options.domain_id + i;
    one.domains = 1;
    one.domain_index = i;
    shards.push_back(make_one_domain(vendor, one));
  }
  return std::make_unique<ShardedTransport>(std::move(shards));
}

std::optional<wire::AnyMessage> decode_serialized(wire::MessageKind kind, std::span<const std::byte> bytes) {
#if defined(RETREAT_HAVE_FASTDDS)
  return decode_fastdds(kind, bytes);
#elif defined(RETREAT_HAVE_CYCLONEDDS)
  return decode_cyclonedds(kind, bytes);
#else
  (void)kind;
  (void)bytes;
  throw std::logic_error("decoding serialized samples needs a DDS adapter in this build");
#endif
}

}  // namespace retreat::transport
