#pragma once
// The viewer's drawn frames, timed on the UI thread (--frame-times FILE): when each began, how long
// the UI thread worked on it and what simulation step it showed, written as CSV on closing.
#include <string>
#include <vector>

namespace weft {

struct FrameTime {
  double start_s = 0.0;      // wall seconds since the window opened
  double work_ms = 0.0;      // input, panels, taking in the step, drawing: up to the buffer swap
  double interval_ms = 0.0;  // since the previous frame began (the UI's frame time, swap included)
  int shown_step = 0;        // the simulation step drawn (frame x steps per frame + step in frame)
  double step_ms = 0.0;      // that step's wall time on the worker
  double simulated_s = 0.0;  // the simulated time drawn
};

class FrameTimeLog {
 public:
  void add(const FrameTime& frame) { frames_.push_back(frame); }
  // Writes the CSV whole or not at all; throws IoError naming the file.
  void write(const std::string& path) const;

 private:
  std::vector<FrameTime> frames_;
};

}  // namespace weft
