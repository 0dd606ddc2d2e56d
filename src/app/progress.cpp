#include "app/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace weft {

namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

constexpr double bar_refresh_interval_s = 0.1;
constexpr int bar_width = 30;

}  // namespace

ProgressReporter::ProgressReporter(int total_frames, bool enabled, ProgressOptions options)
    : total_frames_(total_frames),
      enabled_(enabled),
      terminal_(::isatty(STDERR_FILENO) != 0),
      options_(std::move(options)),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

std::string ProgressReporter::describe(int frames_done, int steps_done, int steps_per_frame) const {
  const double elapsed = seconds_between(start_, std::chrono::steady_clock::now());
  // Frames with the finished part of the one under way, so a slow frame still moves the rate.
  const bool within_frame = steps_per_frame > 1 && steps_done > 0;
  const double frames = frames_done + (within_frame ? static_cast<double>(steps_done) / steps_per_frame : 0.0);
  const double fps = elapsed > 0.0 ? frames / elapsed : 0.0;
  char text[200];
  if (total_frames_ > 0) {
    const double eta = fps > 0.0 ? (total_frames_ - frames) / fps : 0.0;
    std::snprintf(text, sizeof text, "%d/%d frames", frames_done, total_frames_);
    std::string line = text;
    if (within_frame) {
      std::snprintf(text, sizeof text, " (frame %d: step %d/%d)", frames_done + 1, steps_done, steps_per_frame);
      line += text;
    }
    std::snprintf(text, sizeof text, "  %.2g frames/s  elapsed %.0fs  ETA %.0fs", fps, elapsed, std::ceil(eta));
    line += text;
    if (unconverged_steps_ > 0) line += "  " + std::to_string(unconverged_steps_) + " steps unconverged";
    return line;
  }
  std::snprintf(text, sizeof text, "%d frames  %.2g frames/s  elapsed %.0fs", frames_done, fps, elapsed);
  return text;
}

void ProgressReporter::update(int frames_done, int steps_done, int steps_per_frame) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (seconds_between(start_, now) < options_.quiet_for_s) return;
  const double since_last = seconds_between(last_print_, now);
  if (terminal_) {
    if (since_last < bar_refresh_interval_s && (total_frames_ <= 0 || frames_done < total_frames_)) return;
  } else if (since_last < options_.line_interval_s && (printed_ || options_.quiet_for_s <= 0.0)) {
    return;  // plain lines: the first right after the quiet time, then one per interval
  }
  const std::string prefix = options_.label.empty() ? "" : options_.label + ": ";
  const std::string text = describe(frames_done, steps_done, steps_per_frame);
  if (terminal_) {
    if (total_frames_ > 0) {
      const int filled = std::min(bar_width, bar_width * frames_done / total_frames_);
      std::fprintf(stderr, "\r%s[%s%s] %s\033[K", prefix.c_str(), std::string(filled, '#').c_str(),
                   std::string(bar_width - filled, '.').c_str(), text.c_str());
    } else {
      std::fprintf(stderr, "\r%s%s\033[K", prefix.c_str(), text.c_str());
    }
  } else {
    std::fprintf(stderr, "weft: %s%s\n", prefix.c_str(), text.c_str());
  }
  std::fflush(stderr);
  printed_ = true;
  last_print_ = now;
}

void ProgressReporter::finish(int frames_done) {
  if (!enabled_) return;
  const bool was_quiet = seconds_between(start_, std::chrono::steady_clock::now()) < options_.quiet_for_s;
  if (was_quiet && !printed_) return;
  last_print_ = std::chrono::steady_clock::time_point{};  // force the last report out
  update(frames_done);
  if (terminal_) std::fprintf(stderr, "\n");
}

}  // namespace weft
