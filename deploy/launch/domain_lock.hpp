#pragma once
/// @file
/// One DDS domain per swarm on a host: a launcher holds /tmp/retreat-domain-<id>.lock (flock)
/// for as long as its run lasts, so that two launches never share a domain.

#include <optional>
#include <string>

namespace retreat::launch {

class DomainLock {
 public:
  /// Locks `domain` if no other launcher holds it; nullopt otherwise.
  static std::optional<DomainLock> try_lock(int domain);
  /// Locks the first free domain in [first, last]; throws std::runtime_error if none is free.
  static DomainLock pick_free(int first, int last);

  DomainLock(DomainLock&& other) noexcept : fd_(other.fd_), domain_(other.domain_) { other.fd_ = -1; }
  DomainLock& operator=(DomainLock&& other) noexcept;
  DomainLock(const DomainLock&) = delete;
  DomainLock& operator=(const DomainLock&) = delete;
  ~DomainLock();

  int domain() const { return domain_; }
  static std::string path(int domain);

 private:
  DomainLock(int fd, int domain) : fd_(fd), domain_(domain) {}
  int fd_ = -1;
  int domain_ = -1;
};

}  // namespace retreat::launch
