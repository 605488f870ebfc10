#include "domain_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdexcept>

namespace retreat::launch {

std::string DomainLock::path(int domain) { return "/tmp/retreat-domain-" + std::to_string(domain) + ".lock"; }

std::optional<DomainLock> DomainLock::try_lock(int domain) {
  // Read-only is enough for flock, and lets users share lock files created by each other.
  const auto file = path(domain);
  const int fd = ::open(file.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) return std::nullopt;
  ::fchmod(fd, 0666);  // best effort (umask); fails harmlessly on another user's file
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    return std::nullopt;
  }
  return DomainLock(fd, domain);
}

DomainLock DomainLock::pick_free(int first, int last) {
  for (int d = first; d <= last; ++d) {
    if (auto lock = try_lock(d)) return std::move(*lock);
  }
  throw std::runtime_error("no free DDS domain id in " + std::to_string(first) + ".." +
                           std::to_string(last) + " (every /tmp/retreat-domain-<id>.lock is held); "
                           "give one with --domain N");
}

DomainLock& DomainLock::operator=(DomainLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    domain_ = other.domain_;
    other.fd_ = -1;
  }
  return *this;
}

DomainLock::~DomainLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

}  // namespace retreat::launch
