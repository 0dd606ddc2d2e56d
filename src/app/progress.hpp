#pragma once
// Progress of a long run on stderr: a live bar on a terminal, a plain line every few seconds
// otherwise (logs of cluster jobs). Headless runs, viewer screenshots and recordings use it.
#include <chrono>
#include <string>

namespace weft {

struct ProgressOptions {
  std::string label;             // "screenshot" prints "weft: screenshot: ..."; empty: "weft: ..."
  double quiet_for_s = 0.0;      // nothing is printed before this much time has passed
  double line_interval_s = 5.0;  // plain lines (not a terminal) at most this often
};

class ProgressReporter {
 public:
  // `total_frames` <= 0: open-ended, counted without a total or an ETA.
  ProgressReporter(int total_frames, bool enabled, ProgressOptions options = {});
  // Reports that `frames_done` of the total are complete and, within the next frame,
  // `steps_done` of its `steps_per_frame` steps (a long frame shows where it is).
  void update(int frames_done, int steps_done = 0, int steps_per_frame = 0);
  // Counts implicit steps that ended unconverged; the line shows the count once it is not 0.
  void add_unconverged_steps(int steps) { unconverged_steps_ += steps; }
  // Ends the bar's line (terminal) or prints the last line; silent if nothing was printed
  // and the run took less than quiet_for_s.
  void finish(int frames_done);

 private:
  std::string describe(int frames_done, int steps_done, int steps_per_frame) const;

  int total_frames_;
  int unconverged_steps_ = 0;
  bool enabled_;
  bool terminal_;
  ProgressOptions options_;
  bool printed_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace weft
