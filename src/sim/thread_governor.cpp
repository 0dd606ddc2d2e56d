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
  steps_until_probe_ = first_probe_after;
  recent_count_ = 0;
  probe_count_ = 0;
  after_count_ = 0;
}

double ThreadGovernor::median(Window values) {
  std::nth_element(values.begin(), values.begin() + probe_steps / 2, values.end());
  return values[probe_steps / 2];
}

void ThreadGovernor::record(double step_seconds) {
  if (requested_ == 1) return;
  switch (phase_) {
    case Phase::run:
      recent_[recent_count_ % probe_steps] = step_seconds;  // the order within the window is irrelevant
      ++recent_count_;
      if (--steps_until_probe_ <= 0 && recent_count_ >= probe_steps) phase_ = Phase::probe;
      return;
    case Phase::probe:
      probe_[probe_count_++] = step_seconds;
      if (probe_count_ == probe_steps) phase_ = Phase::after_probe;
      return;
    case Phase::after_probe:
      after_[after_count_++] = step_seconds;
      if (after_count_ < probe_steps) return;
      break;
  }
  const double current_time = 0.5 * (median(recent_) + median(after_));
  if (median(probe_) < switch_margin * current_time) {
    current_ = other_count();
    wait_ = first_probe_after;
  } else {
    wait_ = std::min(2 * wait_, longest_wait);
  }
  phase_ = Phase::run;
  steps_until_probe_ = wait_;
  recent_count_ = 0;
  probe_count_ = 0;
  after_count_ = 0;
}

}  // namespace weft
