#pragma once
// Adaptive time stepping for the explicit integrators by step doubling: each trial step of h is
// taken once whole and once as two halves from the same start; for an integrator of order p the
// halves' local error is about |x_halves - x_whole| / (2^p - 1) (Richardson), and the step is
// accepted when that estimate is below the tolerance, keeping the halves' result. The next step
// is h * clamp(0.9 (tol / error)^(1/(p+1)), 0.2, 2), kept in [h_min, h_max]. A step past the
// stability limit makes the two answers part (or overflow), so it is rejected and shrunk rather
// than accepted with a small estimate. At h_min a step whose estimate is still above the
// tolerance is taken and counted (AdaptiveState::unmet): the tolerance was not met, and the caller
// says so rather than report a bounded error.
#include "physics/cloth.hpp"
#include "physics/explicit_midpoint.hpp"
#include "physics/integrator.hpp"

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
  int unmet = 0;             // steps taken at h_min with the estimate above the tolerance (cumulative)
  double last_error = 0.0;   // m, error estimate of the last accepted step
};

// Advances the cloth by exactly `duration` with adaptive steps of `kind` (symplectic_euler,
// midpoint_euler_cromer or explicit_midpoint). `trial` holds the whole step's answer.
void adaptive_advance(Cloth& cloth, IntegratorKind kind, const Vec3& gravity, double duration,
                      const AdaptiveSettings& settings, AdaptiveState& state, ExplicitWorkspace& workspace,
                      ClothState& trial);

}  // namespace weft
