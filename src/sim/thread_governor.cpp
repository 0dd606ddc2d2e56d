#include "sim/thread_governor.hpp"

#include <algorithm>

namespace weft {

void ThreadGovernor::set_requested(int requested) {
  requested = std::max(1, requested);
  if (requested == requested_) return;
  requested_ = requested;
  current_ = requested;
  probing_ = false;
  wait_ = first_probe_after;
  steps_until_probe_ = first_probe_after;
  recent_count_ = 0;
  probe_count_ = 0;
}

double ThreadGovernor::median(Window values) {
  std::nth_element(values.begin(), values.begin() + probe_steps / 2, values.end());
  return values[probe_steps / 2];
}

void ThreadGovernor::record(double step_seconds) {
  if (requested_ == 1) return;
  if (probing_) {
    probe_[probe_count_++] = step_seconds;
    if (probe_count_ < probe_steps) return;
    probing_ = false;
    if (median(probe_) < switch_margin * median(recent_)) {
      current_ = other_count();
      wait_ = first_probe_after;
    } else {
      wait_ = std::min(2 * wait_, longest_wait);
    }
    steps_until_probe_ = wait_;
    recent_count_ = 0;
    probe_count_ = 0;
    return;
  }
  recent_[recent_count_ % probe_steps] = step_seconds;  // the order within the window is irrelevant
  ++recent_count_;
  if (--steps_until_probe_ <= 0 && recent_count_ >= probe_steps) probing_ = true;
}

}  // namespace weft
