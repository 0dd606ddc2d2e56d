#include "ui/stats_history.hpp"

#include <algorithm>

namespace weft {

void Series::push(float value) {
  if (static_cast<int>(values_.size()) < capacity_) {
    values_.push_back(value);
    return;
  }
  values_[static_cast<size_t>(start_)] = value;
  start_ = (start_ + 1) % capacity_;
}

const std::vector<float>& Series::values() const {
  ordered_.assign(values_.begin() + start_, values_.end());
  ordered_.insert(ordered_.end(), values_.begin(), values_.begin() + start_);
  return ordered_;
}

float Series::last() const {
  if (values_.empty()) return 0.0f;
  return values_[static_cast<size_t>((start_ + static_cast<int>(values_.size()) - 1) % static_cast<int>(values_.size()))];
}

float Series::max() const { return values_.empty() ? 0.0f : *std::max_element(values_.begin(), values_.end()); }

void StatsHistory::record(const World& world) {
  const Energies energies = world.energies();
  const StepStats& stats = world.last_step_stats();
  kinetic.push(static_cast<float>(energies.kinetic));
  potential.push(static_cast<float>(energies.gravitational + energies.elastic));
  integrate_ms.push(static_cast<float>(stats.integrate_ms));
  collisions_ms.push(static_cast<float>(stats.collisions_ms));
  prepare_collisions_ms.push(static_cast<float>(stats.prepare_collisions_ms));
  newton_iterations.push(static_cast<float>(stats.newton_iterations));
}

void StatsHistory::clear() {
  for (Series* series :
       {&kinetic, &potential, &integrate_ms, &collisions_ms, &prepare_collisions_ms, &newton_iterations}) {
    series->clear();
  }
}

}  // namespace weft
