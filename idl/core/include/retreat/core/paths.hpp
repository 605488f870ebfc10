#pragma once
/// @file
/// File-system questions that never throw. A path given on a command line, in a scenario or in
/// a profile may be anything (5,000 characters, a loop of links, a directory without
/// permission): the throwing std::filesystem overloads then end the program, these answer false
/// (found by tests/fuzz: a long `dds.profile` made every program abort).

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

namespace retreat {

/// Whether @p path names a regular file (false for any path the OS refuses).
inline bool is_regular_file(const std::string& path) noexcept {
  std::error_code ignored;
  return std::filesystem::is_regular_file(path, ignored);
}

/// Whether @p path names a directory (false for any path the OS refuses).
inline bool is_directory(const std::string& path) noexcept {
  std::error_code ignored;
  return std::filesystem::is_directory(path, ignored);
}

/// Whether anything exists at @p path (false for any path the OS refuses).
inline bool exists(const std::string& path) noexcept {
  std::error_code ignored;
  return std::filesystem::exists(path, ignored);
}

/// The bytes of the file @p path, a regular file or a pipe (a secret given as `<(command)`), or
/// nothing when it is neither (missing, a directory, a device, any path the OS refuses) or
/// reading it fails. Never throws for what the file system holds: an std::ifstream opens a
/// directory, and its first read throws std::ios_base::failure (found by tests/fuzz:
/// `retreat-bridge --token-file DIR` ended without naming the file).
std::optional<std::string> read_file(const std::string& path);

}  // namespace retreat
