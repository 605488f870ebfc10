#pragma once
/// @file
/// An agent's journal of the frames it accepted, so that an agent restarted mid-run resumes its
/// window, its steps and its coins where the dead one stopped (`retreat-agent --journal FILE`,
/// docs/protocol.md §6, "A restarted agent").

#include <cstdio>
#include <string>
#include <vector>

#include "retreat/scenario/params.hpp"
#include "retreat/wire/messages.hpp"

namespace retreat::agent {

/// The first line of robot @p robot_id's journal under @p scenario: the journal version, the
/// robot and a fingerprint of everything its decisions depend on (seed, model, agent).
std::string journal_header(const scenario::Scenario& scenario, wire::RobotId robot_id);

/// An append-only text file: the header line, then one line per accepted frame
/// (`tick,time,phase,in_contact,new_onsets`, the time with 17 significant digits), each written
/// and flushed to the operating system before the frame is answered.
class FrameJournal {
 public:
  /// Opens @p path, creating it with @p header when it is missing or empty. An existing journal
  /// must start with @p header; its frames are read into recovered() and new ones go after them.
  /// A last line without its newline (the process died while writing it) is cut off.
  /// @throws std::invalid_argument naming the file, the line and what is wrong (another robot,
  ///         seed or parameters; an unreadable line); std::runtime_error if it cannot be written.
  FrameJournal(std::string path, const std::string& header, wire::RobotId robot_id);
  ~FrameJournal();
  FrameJournal(const FrameJournal&) = delete;
  FrameJournal& operator=(const FrameJournal&) = delete;

  /// Frames journalled by earlier processes, in order.
  const std::vector<wire::ProximityFrame>& recovered() const { return recovered_; }
  /// Appends @p frame and flushes it. Returns false if the write failed (the frame is still
  /// acted on; the journal is then incomplete and says so on stderr once).
  bool append(const wire::ProximityFrame& frame);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::vector<wire::ProximityFrame> recovered_;
  bool failed_ = false;
};

}  // namespace retreat::agent
