#pragma once
// Picks how many of the requested solver threads a step runs on, by measuring.
//
// On a node shared with another process, a thread that shares its core runs at about half speed
// and every barrier of the step waits for it: two threads were slower than one on the 64x64
// drape with a busy loop holding one of two cores (docs/performance.md, "Threads on a shared
// node"). The governor runs the requested count and, now and then, a short probe of steps on
// the other count (one thread when running many, many when running one); it keeps whichever
// ran the steps faster. Results never depend on the thread count (core/parallel_chunks.hpp:
// sums are added in chunk order), so switching changes how fast a run goes, never what it
// computes.
//
// Probe: `probe_steps` steps on the other count, then `probe_steps` on the current count again;
// the probe's median step time is compared with the mean of the medians of the windows just
// before and just after it, so that a trend in the steps' cost (a cloth reaching a collider
// costs several times more a step within a few frames) cancels to first order. The first probe
// comes after `first_probe_after` steps; each probe that confirms the current count doubles the
// wait to the next (up to `longest_wait`), a switch resets it, so a run that never needs to
// switch spends a few steps in a thousand probing.
#include <array>

namespace weft {

class ThreadGovernor {
 public:
  static constexpr int probe_steps = 5;
  static constexpr int first_probe_after = 20;
  static constexpr int longest_wait = 2560;
  // A probe must be this much faster (median step time) to switch: noise does not flip it.
  static constexpr double switch_margin = 0.9;

  // `requested` threads (1: the governor never probes).
  void set_requested(int requested);
  int requested() const { return requested_; }
  // Threads for the next step.
  int threads() const { return phase_ == Phase::probe ? other_count() : current_; }
  // Reports the wall time of the step just run on threads().
  void record(double step_seconds);

 private:
  int other_count() const { return current_ == 1 ? requested_ : 1; }
  using Window = std::array<double, probe_steps>;
  static double median(Window values);

  enum class Phase { run, probe, after_probe };

  int requested_ = 1;
  int current_ = 1;
  Phase phase_ = Phase::run;
  int wait_ = first_probe_after;  // steps on current_ before the next probe
  int steps_until_probe_ = first_probe_after;
  Window recent_{};  // the last step times on current_ (a ring, recent_count_ filled)
  int recent_count_ = 0;
  Window probe_{};  // step times of the probe under way
  int probe_count_ = 0;
  Window after_{};  // step times on current_ after the probe
  int after_count_ = 0;
};

}  // namespace weft
