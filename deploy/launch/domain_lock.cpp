#include "domain_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdexcept>

namespace retreat::launch {

std::string DomainLock::path(int domain) { return "/tmp/retreat-domain-" + std::to_string(domain) + ".lock"; }

std::optional<DomainLock> DomainLock::try_lock(int domain, int count) {
  std::vector<int> fds;
  const auto give_up = [&] {
    for (const int fd : fds) ::close(fd);
    return std::nullopt;
  };
  for (int d = domain; d < domain + count; ++d) {
    // Read-only is enough for flock, and lets users share lock files created by each other.
    const auto file = path(d);
    const int fd = ::open(file.c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) return give_up();
    ::fchmod(fd, 0666);  // best effort (umask); fails harmlessly on another user's file
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd);
      return give_up();
    }
    fds.push_back(fd);
  }
  return DomainLock(std::move(fds), domain);
}

DomainLock DomainLock::pick_free(int first, int last, int count) {
  for (int d = first; d <= last; ++d) {
    if (auto lock = try_lock(d, count)) return std::move(*lock);
  }
  const std::string what = count == 1 ? "no free DDS domain id" : "no " + std::to_string(count) + " consecutive free DDS domain ids";
  throw std::runtime_error(what + " from " + std::to_string(first) + ".." + std::to_string(last) +
                           " on (every /tmp/retreat-domain-<id>.lock is held); give one with --domain N");
}

void DomainLock::release() {
  for (const int fd : fds_) ::close(fd);  // closing releases the lock
  fds_.clear();
}

DomainLock& DomainLock::operator=(DomainLock&& other) noexcept {
  if (this != &other) {
    release();
    fds_ = std::move(other.fds_);
    other.fds_.clear();
    domain_ = other.domain_;
  }
  return *this;
}

DomainLock::~DomainLock() { release(); }

}  // namespace retreat::launch
