#pragma once
// Progress of a headless run on stderr: a live bar on a terminal, a plain line every few
// seconds otherwise (logs of cluster jobs).
#include <chrono>
#include <string>

namespace weft {

class ProgressReporter {
 public:
  ProgressReporter(int total_frames, bool enabled);
  // Reports that `frames_done` of the total are complete.
  void update(int frames_done);
  // Counts implicit steps that ended unconverged; the line shows the count once it is not 0.
  void add_unconverged_steps(int steps) { unconverged_steps_ += steps; }
  // Ends the bar's line (terminal) or prints the last line.
  void finish(int frames_done);

 private:
  std::string describe(int frames_done) const;

  int total_frames_;
  int unconverged_steps_ = 0;
  bool enabled_;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
};

}  // namespace weft
