#pragma once
/// @file
/// One DDS domain per swarm on a host: a launcher holds /tmp/retreat-domain-<id>.lock (flock)
/// for as long as its run lasts, so that two launches never share a domain; a swarm on several
/// domains (`dds.domains`) holds every one of them.

#include <optional>
#include <string>
#include <vector>

namespace retreat::launch {

class DomainLock {
 public:
  /// Locks domains `domain` .. `domain + count - 1` if no other launcher holds any of them;
  /// nullopt otherwise.
  static std::optional<DomainLock> try_lock(int domain, int count = 1);
  /// Locks the first `count` consecutive free domains starting in [first, last]; throws
  /// std::runtime_error if there are none.
  static DomainLock pick_free(int first, int last, int count = 1);

  DomainLock(DomainLock&& other) noexcept : fds_(std::move(other.fds_)), domain_(other.domain_) { other.fds_.clear(); }
  DomainLock& operator=(DomainLock&& other) noexcept;
  DomainLock(const DomainLock&) = delete;
  DomainLock& operator=(const DomainLock&) = delete;
  ~DomainLock();

  /// The first domain held.
  int domain() const { return domain_; }
  static std::string path(int domain);

 private:
  DomainLock(std::vector<int> fds, int domain) : fds_(std::move(fds)), domain_(domain) {}
  void release();
  std::vector<int> fds_;
  int domain_ = -1;
};

}  // namespace retreat::launch
