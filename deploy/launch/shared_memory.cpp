#include "shared_memory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

namespace retreat::launch {

namespace fs = std::filesystem;

namespace {

/// True when nobody holds `lock_file`'s flock (its owner is dead); false when held or unreadable.
bool owner_dead(const fs::path& lock_file) {
  const int fd = ::open(lock_file.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return false;
  const bool acquired = ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  ::close(fd);  // releases the lock if we took it
  return acquired;
}

std::uint64_t remove_file(const fs::path& p) {
  std::error_code ec;
  const auto size = fs::is_regular_file(p, ec) ? fs::file_size(p, ec) : 0;
  return fs::remove(p, ec) && !ec ? size : 0;
}

}  // namespace

ShmCleanup remove_stale_fastdds_segments(const std::string& dir) {
  ShmCleanup out;
  std::error_code ec;
  std::vector<fs::path> locks;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const auto name = entry.path().filename().string();
    if (name.rfind("fastrtps_", 0) == 0 && name.size() > 3 &&
        name.compare(name.size() - 3, 3, "_el") == 0) {
      locks.push_back(entry.path());
    }
  }
  for (const auto& lock : locks) {
    if (!owner_dead(lock)) continue;
    const auto lock_name = lock.filename().string();
    const std::string segment = lock_name.substr(0, lock_name.size() - 3);
    out.bytes += remove_file(fs::path(dir) / segment);
    out.bytes += remove_file(fs::path(dir) / ("sem." + segment + "_mutex"));
    out.bytes += remove_file(lock);
    ++out.segments;
  }
  return out;
}

bool profile_uses_shared_memory(const std::string& path) {
  if (path.empty()) return false;
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  // Comments may name the elements; only the XML itself counts.
  const auto xml = std::regex_replace(text.str(), std::regex("<!--[\\s\\S]*?-->"), "");
  if (std::regex_search(xml, std::regex("<type>\\s*SHM\\s*</type>"))) return true;
  return !std::regex_search(
      xml, std::regex("<useBuiltinTransports>\\s*false\\s*</useBuiltinTransports>"));
}

std::uint64_t free_bytes(const std::string& dir) {
  struct statvfs s {};
  if (::statvfs(dir.c_str(), &s) != 0) return 0;
  return static_cast<std::uint64_t>(s.f_bavail) * s.f_frsize;
}

}  // namespace retreat::launch
