#include "app/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace weft {

namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

constexpr double plain_line_interval_s = 5.0;
constexpr double bar_refresh_interval_s = 0.1;
constexpr int bar_width = 30;

}  // namespace

ProgressReporter::ProgressReporter(int total_frames, bool enabled)
    : total_frames_(total_frames),
      enabled_(enabled),
      terminal_(::isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

std::string ProgressReporter::describe(int frames_done) const {
  const double elapsed = seconds_between(start_, std::chrono::steady_clock::now());
  const double fps = elapsed > 0.0 ? frames_done / elapsed : 0.0;
  const double eta = fps > 0.0 ? (total_frames_ - frames_done) / fps : 0.0;
  char text[160];
  std::snprintf(text, sizeof text, "%d/%d frames  %.1f frames/s  elapsed %.0fs  ETA %.0fs", frames_done,
                total_frames_, fps, elapsed, std::ceil(eta));
  std::string line = text;
  if (unconverged_steps_ > 0) line += "  " + std::to_string(unconverged_steps_) + " steps unconverged";
  return line;
}

void ProgressReporter::update(int frames_done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double since_last = seconds_between(last_print_, now);
  if (terminal_) {
    if (since_last < bar_refresh_interval_s && frames_done < total_frames_) return;
    const int filled = total_frames_ > 0 ? bar_width * frames_done / total_frames_ : bar_width;
    std::fprintf(stderr, "\r[%s%s] %s  ", std::string(filled, '#').c_str(),
                 std::string(bar_width - filled, '.').c_str(), describe(frames_done).c_str());
  } else {
    if (since_last < plain_line_interval_s) return;
    std::fprintf(stderr, "weft: %s\n", describe(frames_done).c_str());
  }
  std::fflush(stderr);
  last_print_ = now;
}

void ProgressReporter::finish(int frames_done) {
  if (!enabled_) return;
  last_print_ = std::chrono::steady_clock::time_point{};  // force the last report out
  update(frames_done);
  if (terminal_) std::fprintf(stderr, "\n");
}

}  // namespace weft
