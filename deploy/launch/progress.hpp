#pragma once
/// @file
/// The progress line on a terminal (stderr): simulated time, population, ticks per second,
/// lost agents. Only drawn when stderr is a terminal; messages are printed either way.

#include <chrono>
#include <cstdint>
#include <string>

#include "retreat/wire/messages.hpp"

namespace retreat::launch {

class ProgressLine {
 public:
  /// `label` prefixes the line (scenario and seed); `duration` is run.duration [s].
  ProgressLine(std::string label, double duration);
  ~ProgressLine();

  bool enabled() const { return tty_; }
  /// Redraws the line (at most a few times per second, unless `force`).
  void show(const wire::ArenaTelemetry& t, bool force = false);
  /// Redraws with a status text while nothing is known yet ("waiting for 12 agents").
  void show_status(const std::string& text);
  /// Prints one line (erasing the progress line first; it is redrawn by the next show()).
  void message(const std::string& line);
  /// Leaves the last progress line on the terminal.
  void finish();

 private:
  void draw(const std::string& text, bool force);
  std::string label_;
  double duration_;
  bool tty_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace retreat::launch
