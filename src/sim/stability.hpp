#pragma once
// Detects a run that has gone wrong: a non-finite position or velocity, a vertex faster than a
// bound, or a spring or membrane triangle stretched past a bound. The finding names the cloth,
// the vertex and the force term most to blame, so the message says where to look.
#include <string>

#include "sim/world.hpp"

namespace weft {

struct StabilityLimits {
  double max_speed = 100.0;  // m/s; 0: no bound
  double max_strain = 5.0;   // stretch - 1: |d| / rest_length - 1 for springs, sqrt(1 + 2 e_max) - 1
                             // for membrane triangles (e_max: largest principal Green strain); 0: no bound
};

struct Instability {
  bool found = false;
  int cloth = -1;
  int vertex = -1;
  std::string cloth_name;
  std::string quantity;     // "position", "velocity", "speed", "strain" (a spring) or "membrane_strain"
  double value = 0.0;       // the offending speed or strain (NaN/Inf for non-finite values)
  int element = -1;         // the stretched spring or membrane triangle (strain quantities)
  std::string term;         // the force term with the largest (or a non-finite) force on the vertex
  double term_force = 0.0;  // N, that force's magnitude
  std::string describe() const;
};

// Non-finite values and speed: cheap (one pass over x and v), meant for every step.
Instability check_state(const World& world, const StabilityLimits& limits);
// Spring and membrane strain: one pass over the springs and the membrane triangles.
Instability check_strain(const World& world, const StabilityLimits& limits);
// The largest strain (stretch - 1) over every spring and membrane triangle; 0 when none is stretched.
double largest_strain(const World& world);

}  // namespace weft
