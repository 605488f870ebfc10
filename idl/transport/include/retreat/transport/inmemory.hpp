#pragma once
/// @file
/// The in-memory transport: the same interface, delivery inside one process, synchronous on
/// the writer's thread. For unit tests and fast sweeps; never a stand-in for a DDS claim.
/// It follows the DDS matching rules the project relies on: same topic and type; a best-effort
/// writer does not match a reliable reader; a volatile writer does not match a transient-local
/// reader; transient-local writers replay the last `depth` samples per instance to late readers.

#include <memory>

#include "retreat/transport/transport.hpp"

namespace retreat::transport {

class InMemoryBus;

/// A bus is one "domain" of the in-memory transport. Threading::confined: one thread creates,
/// writes, takes and destroys everything on it (a whole swarm stepped in one thread), so
/// nothing locks; Threading::shared: any thread may.
std::shared_ptr<InMemoryBus> make_inmemory_bus(Threading threading = Threading::shared);

/// The process-wide bus for a domain id (what make_transport("inmemory", ...) uses).
std::shared_ptr<InMemoryBus> inmemory_bus_for_domain(int domain_id);

std::unique_ptr<Transport> make_inmemory_transport(std::shared_ptr<InMemoryBus> bus,
                                                   const ParticipantOptions& options);

}  // namespace retreat::transport
