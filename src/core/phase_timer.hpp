#pragma once
// Wall time of the step's phases: milliseconds since a time point, and a scope that adds its
// own duration to a counter when it ends.
#include <chrono>

namespace weft {

using PhaseClock = std::chrono::steady_clock;

inline double milliseconds_since(PhaseClock::time_point start) {
  return std::chrono::duration<double, std::milli>(PhaseClock::now() - start).count();
}

// Adds the time from construction to the end of the scope to `total_ms`.
class PhaseTimer {
 public:
  explicit PhaseTimer(double& total_ms) : total_ms_(total_ms), start_(PhaseClock::now()) {}
  ~PhaseTimer() { total_ms_ += milliseconds_since(start_); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& total_ms_;
  PhaseClock::time_point start_;
};

}  // namespace weft
