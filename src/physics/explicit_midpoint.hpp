#pragma once
// Explicit midpoint (second-order Runge-Kutta):
//   x_m = x + h/2 v,  v_m = v + h/2 M^-1 f(x, v)
//   x' = x + h v_m,   v' = v + h M^-1 f(x_m, v_m)
// Local error O(h^3), global error O(h^2). Not symplectic: on an undamped oscillation of
// frequency w each step multiplies the amplitude by sqrt(1 + (wh)^4 / 4), so it has no stable
// step without damping; Volino et al. 1995's second-order scheme is midpoint_euler_cromer.hpp. Kept
// as the adaptive stepper's second-order partner (adaptive_stepping.hpp) and for comparison.
#include "physics/cloth.hpp"

namespace weft {

// Scratch for the explicit integrators, allocated once per cloth.
struct ExplicitWorkspace {
  Positions x_start, v_start;   // state at the start of the step (3 x n)
  Positions x_mid, v_mid;       // midpoint state (3 x n)
  Positions force;              // force scratch (3 x n)
  void resize(int num_vertices);
};

void explicit_midpoint_step(Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace);

}  // namespace weft
