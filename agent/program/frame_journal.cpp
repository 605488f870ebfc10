#include "retreat/agent/frame_journal.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "retreat/core/paths.hpp"
#include "retreat/scenario/json.hpp"

namespace retreat::agent {
namespace {

/// FNV-1a, 64 bits: a fingerprint, not a security property.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

template <class T>
bool parse_field(std::string_view text, T& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size();
}

/// One journal line, or why it is not one.
std::string parse_line(const std::string& line, wire::RobotId robot, wire::ProximityFrame& f) {
  std::vector<std::string_view> fields;
  std::string_view rest(line);
  for (;;) {
    const auto comma = rest.find(',');
    fields.push_back(rest.substr(0, comma));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (fields.size() != 5) return "expected 5 fields (tick,time,phase,in_contact,new_onsets), found " + std::to_string(fields.size());
  unsigned phase = 0;
  unsigned contact = 0;
  f.robot_id = robot;
  if (!parse_field(fields[0], f.tick) || f.tick < 0) return "tick '" + std::string(fields[0]) + "' is not a whole number >= 0";
  // strtod, not from_chars: the libc++ of the portability build has no from_chars for double.
  const std::string time_text(fields[1]);
  char* end = nullptr;
  f.time = std::strtod(time_text.c_str(), &end);
  if (time_text.empty() || *end != '\0' || !std::isfinite(f.time) || f.time < 0.0) {
    return "time '" + time_text + "' is not a finite number >= 0";
  }
  if (!parse_field(fields[2], phase) || phase >= wire::phase_count) return "phase '" + std::string(fields[2]) + "' is not 0..3";
  f.phase = static_cast<wire::Phase>(phase);
  if (!parse_field(fields[3], contact) || contact > 1) return "in_contact '" + std::string(fields[3]) + "' is not 0 or 1";
  f.in_contact = contact == 1;
  if (!parse_field(fields[4], f.new_onsets)) return "new_onsets '" + std::string(fields[4]) + "' is not a whole number >= 0";
  return "";
}

}  // namespace

std::string journal_header(const scenario::Scenario& scenario, wire::RobotId robot_id) {
  // What decisions depend on: the seed, the model and the agent's parameters (not the DDS
  // settings, the run's mode or the arena: a restart may change those).
  scenario::Scenario relevant;
  relevant.seed = scenario.seed;
  relevant.model = scenario.model;
  relevant.agent = scenario.agent;
  std::ostringstream header;
  header << "# retreat-agent journal 1 robot=" << robot_id << " fingerprint=" << std::hex
         << fnv1a(scenario::dump_json(relevant));
  return header.str();
}

FrameJournal::FrameJournal(std::string path, const std::string& header, wire::RobotId robot_id)
    : path_(std::move(path)) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool fresh = !fs::exists(path_, ec) || fs::file_size(path_, ec) == 0;
  if (!fresh) {
    const auto read = retreat::read_file(path_);
    if (!read) throw std::invalid_argument("--journal '" + path_ + "' cannot be read as a file");
    const std::string& text = *read;
    const auto complete = text.rfind('\n');  // a torn last line is cut off
    const std::size_t keep = complete == std::string::npos ? 0 : complete + 1;
    std::istringstream lines(text.substr(0, keep));
    std::string line;
    std::size_t number = 0;
    while (std::getline(lines, line)) {
      ++number;
      if (number == 1) {
        if (line != header) {
          throw std::invalid_argument("--journal '" + path_ + "' line 1: '" + line +
                                      "' is another robot's, seed's or parameters' journal (this agent writes '" +
                                      header + "')");
        }
        continue;
      }
      wire::ProximityFrame f;
      if (const auto why = parse_line(line, robot_id, f); !why.empty()) {
        throw std::invalid_argument("--journal '" + path_ + "' line " + std::to_string(number) + ": " + why);
      }
      recovered_.push_back(f);
    }
    if (number == 0) {
      throw std::invalid_argument("--journal '" + path_ + "': no complete header line; remove the file to start afresh");
    }
    if (keep < text.size()) fs::resize_file(path_, keep);
  }
  file_ = std::fopen(path_.c_str(), "ab");
  if (file_ == nullptr) {
    throw std::invalid_argument("--journal '" + path_ + "' cannot be written: " + std::strerror(errno));
  }
  if (fresh && (std::fprintf(file_, "%s\n", header.c_str()) < 0 || std::fflush(file_) != 0)) {
    std::fclose(file_);
    throw std::runtime_error("--journal '" + path_ + "': writing the header failed: " + std::strerror(errno));
  }
}

FrameJournal::~FrameJournal() {
  if (file_ != nullptr) std::fclose(file_);
}

bool FrameJournal::append(const wire::ProximityFrame& f) {
  const bool ok = std::fprintf(file_, "%lld,%.17g,%u,%d,%u\n", static_cast<long long>(f.tick), f.time,
                               static_cast<unsigned>(f.phase), f.in_contact ? 1 : 0, f.new_onsets) > 0 &&
                  std::fflush(file_) == 0;
  if (!ok && !failed_) {
    failed_ = true;
    std::fprintf(stderr, "retreat-agent robot %u: writing the journal '%s' failed (%s); a restart will not "
                 "resume past this frame\n", f.robot_id, path_.c_str(), std::strerror(errno));
  }
  return ok;
}

}  // namespace retreat::agent
