#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace retreat::launch {

ProgressLine::ProgressLine(std::string label, double duration)
    : label_(std::move(label)), duration_(duration), tty_(::isatty(STDERR_FILENO) == 1) {}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::draw(const std::string& text, bool force) {
  if (!tty_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && drawn_ && now - last_ < std::chrono::milliseconds(250)) return;
  last_ = now;
  std::fprintf(stderr, "\r\033[K%s", text.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressLine::show(const wire::ArenaTelemetry& t, bool force) {
  char text[256];
  std::snprintf(text, sizeof text,
                "[%s] t %.1f/%.0f s | inside %u waiting %u retreating %u departed %u | "
                "%.0f ticks/s | lost agents %u",
                label_.c_str(), t.time, duration_, t.inside, t.waiting, t.retreating, t.departed,
                t.ticks_per_second, t.lost_agents);
  draw(text, force);
}

void ProgressLine::show_status(const std::string& status) { draw("[" + label_ + "] " + status, false); }

void ProgressLine::message(const std::string& line) {
  if (tty_ && drawn_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
  drawn_ = false;
}

void ProgressLine::finish() {
  if (tty_ && drawn_) {
    std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace retreat::launch
