#pragma once
// Picks how many of the requested solver threads a step runs on, by measuring.
//
// On a node shared with another process, a thread that shares its core runs at about half speed
// and every barrier of the step waits for it, so two threads can be slower than one
// (docs/performance.md, "Threads"). The governor runs the requested count and, now and then, a
// short probe of steps on the other count (one thread when running many, many when running one);
// it keeps whichever ran the steps faster. Results never depend on the thread count
// (core/parallel_chunks.hpp: sums are added in chunk order), so switching changes how fast a run
// goes, never what it computes.
//
// Probe: `probe_blocks` blocks of four steps, other - current - current - other. A block's
// ratio is the other count's two step times over the current count's two; a step cost that
// rises or falls steadily (a cloth reaching a collider costs several times more a step within
// a few frames) cancels in it exactly, and the median over the blocks ignores a block that a
// sudden jump falls into. A probe ends after its first block when that block settles the
// question for the current count: the other count clearly slower (block ratio above
// `clear_margin`) and each of its two steps slower than either of the current count's, so a
// single slow step cannot end it. That is the common case (two threads on a free machine, one
// on a shared one), and it runs two steps on the slower count instead of six; a switch always
// takes the whole probe. The first probe comes after `first_probe_after` steps; each probe
// that confirms the current count doubles the wait to the next (quadruples it when the other
// count was clearly slower; up to `longest_wait`), a switch resets it, so a run that never
// needs to switch spends a few steps in a thousand probing. Since which count is faster
// depends on the work a step holds (a free-falling cloth's cheap steps gain little from a
// second thread), a step cost that has moved by more than `regime_factor` from the one the
// last probe measured (median of `regime_window` steps) starts a probe at once, no sooner than
// `first_probe_after` steps after the last; it leaves the wait as it was, so a cost that swings
// back and forth does not keep the probes frequent.
#include <array>

namespace weft {

class ThreadGovernor {
 public:
  static constexpr int probe_blocks = 3;
  static constexpr int probe_steps = 4 * probe_blocks;  // half of them on the other count
  static constexpr int first_probe_after = 20;
  static constexpr int longest_wait = 2560;
  // The median block ratio must be below this to switch: noise does not flip it.
  static constexpr double switch_margin = 0.9;
  // A probe whose median ratio is above this (the other count clearly slower) quadruples the
  // wait instead of doubling it: a short run does not pay for probes of a settled question.
  static constexpr double clear_margin = 1.25;
  static constexpr double regime_factor = 3.0;
  static constexpr int regime_window = 5;

  // `requested` threads (1: the governor never probes).
  void set_requested(int requested);
  int requested() const { return requested_; }
  // The count the governor runs on between probes.
  int current() const { return current_; }
  // Threads for the next step.
  int threads() const {
    return phase_ == Phase::probe && on_other_count(probe_count_) ? other_count() : current_;
  }
  // Reports the wall time of the step just run on threads().
  void record(double step_seconds);

 private:
  int other_count() const { return current_ == 1 ? requested_ : 1; }
  // Whether step k of a probe runs on the other count (the first and last of each block).
  static bool on_other_count(int k) { return k % 4 == 0 || k % 4 == 3; }
  // Whether the probe's first block shows the other count clearly slower (see above).
  bool first_block_settles() const;
  // Decides on the median ratio of the probe's first `blocks` blocks.
  void finish_probe(int blocks);

  enum class Phase { run, probe };

  int requested_ = 1;
  int current_ = 1;
  Phase phase_ = Phase::run;
  int wait_ = first_probe_after;  // steps on current_ before the next probe
  int steps_since_probe_ = 0;
  std::array<double, probe_steps> probe_{};  // step times of the probe under way
  int probe_count_ = 0;
  double probed_step_time_ = 0.0;               // the current count's mean step time in the last probe
  std::array<double, regime_window> recent_{};  // the last step times on current_ (a ring)
};

}  // namespace weft
