#pragma once
// The last few hundred samples of what the plots show (energies, time per phase, Newton
// iterations), oldest first. No ImGui here.
#include <vector>

#include "sim/world.hpp"

namespace weft {

// A fixed-capacity series of floats: push drops the oldest once full; values() is oldest first.
class Series {
 public:
  explicit Series(int capacity = 300) : capacity_(capacity) {}
  void push(float value);
  void clear() { values_.clear(); start_ = 0; }
  // Oldest first (copied into a scratch buffer kept by the series).
  const std::vector<float>& values() const;
  float last() const;
  float max() const;

 private:
  int capacity_;
  std::vector<float> values_;     // ring buffer
  int start_ = 0;                 // index of the oldest once full
  mutable std::vector<float> ordered_;
};

struct StatsHistory {
  Series kinetic, potential;      // J
  Series integrate_ms, collisions_ms, prepare_collisions_ms;  // per step, ms
  Series newton_iterations;       // per step

  // One sample per drawn frame in which the world stepped: energies now, the last step's stats.
  void record(const World& world);
  void clear();
};

}  // namespace weft
