#pragma once
// Adaptive time stepping for the explicit integrators: each trial step is taken with both
// symplectic Euler (first order) and midpoint (second order); their position difference
// estimates the local error of the first-order step. A step is accepted when that error is
// below the tolerance; the next step size is h * clamp(0.9 sqrt(tol / error), 0.2, 2), kept in
// [h_min, h_max]. The propagated solution is the chosen integrator's own.
#include "physics/cloth.hpp"
#include "physics/integrator.hpp"
#include "physics/midpoint_euler.hpp"

namespace weft {

struct AdaptiveSettings {
  bool enabled = false;
  double tolerance = 1e-4;   // m, largest acceptable local position error per step
  double h_min = 1e-6;       // s
  double h_max = 1e-2;       // s
};

struct AdaptiveState {
  double next_step = 0.0;    // s, the step the controller proposes next (0: not started)
  int accepted = 0;          // steps accepted so far (cumulative)
  int rejected = 0;          // steps rejected so far (cumulative)
  double last_error = 0.0;   // m, error estimate of the last accepted step
};

// Advances the cloth by exactly `duration` with adaptive steps of `kind` (symplectic or midpoint).
void adaptive_advance(Cloth& cloth, IntegratorKind kind, const Vec3& gravity, double duration,
                      const AdaptiveSettings& settings, AdaptiveState& state, ExplicitWorkspace& workspace,
                      ClothState& trial);

}  // namespace weft
