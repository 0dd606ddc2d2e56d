#include "sim/thread_governor.hpp"

#include <algorithm>

namespace weft {

void ThreadGovernor::set_requested(int requested) {
  requested = std::max(1, requested);
  if (requested == requested_) return;
  requested_ = requested;
  current_ = requested;
  phase_ = Phase::run;
  wait_ = first_probe_after;
  steps_since_probe_ = 0;
  probe_count_ = 0;
  probed_step_time_ = 0.0;
}

void ThreadGovernor::record(double step_seconds) {
  if (requested_ == 1) return;
  if (phase_ == Phase::probe) {
    probe_[probe_count_++] = step_seconds;
    if (probe_count_ == 4 && first_block_settles()) {
      finish_probe(1);
    } else if (probe_count_ == probe_steps) {
      finish_probe(probe_blocks);
    }
    return;
  }
  recent_[steps_since_probe_ % regime_window] = step_seconds;  // the order within the ring is irrelevant
  ++steps_since_probe_;
  bool regime_changed = false;
  if (probed_step_time_ > 0.0 && steps_since_probe_ >= std::max(first_probe_after, regime_window)) {
    std::array<double, regime_window> window = recent_;
    std::nth_element(window.begin(), window.begin() + regime_window / 2, window.end());
    const double typical = window[regime_window / 2];
    regime_changed =
        typical > regime_factor * probed_step_time_ || regime_factor * typical < probed_step_time_;
  }
  if (steps_since_probe_ >= wait_ || regime_changed) {
    phase_ = Phase::probe;
    probe_count_ = 0;
  }
}

bool ThreadGovernor::first_block_settles() const {
  const double other_fastest = std::min(probe_[0], probe_[3]);
  const double current_slowest = std::max(probe_[1], probe_[2]);
  return other_fastest > current_slowest && probe_[0] + probe_[3] > clear_margin * (probe_[1] + probe_[2]);
}

void ThreadGovernor::finish_probe(int blocks) {
  std::array<double, probe_blocks> ratios;
  double other_time = 0.0, current_time = 0.0;
  for (int b = 0; b < blocks; ++b) {
    const double* block = probe_.data() + 4 * b;
    const double other = block[0] + block[3], current = block[1] + block[2];
    ratios[b] = other / current;
    other_time += other;
    current_time += current;
  }
  std::nth_element(ratios.begin(), ratios.begin() + blocks / 2, ratios.begin() + blocks);
  const double ratio = ratios[blocks / 2];
  if (ratio < switch_margin) {
    current_ = other_count();
    wait_ = first_probe_after;
    current_time = other_time;  // the reference the regime test compares with is the new count's
  } else {
    wait_ = std::min((ratio > clear_margin ? 4 : 2) * wait_, longest_wait);
  }
  probed_step_time_ = current_time / (2 * blocks);
  phase_ = Phase::run;
  steps_since_probe_ = 0;
  probe_count_ = 0;
}

}  // namespace weft
