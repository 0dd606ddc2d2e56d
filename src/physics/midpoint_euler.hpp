#pragma once
// Explicit midpoint (second-order Runge-Kutta), the seed paper's second-order scheme:
//   x_m = x + h/2 v,  v_m = v + h/2 M^-1 f(x, v)
//   x' = x + h v_m,   v' = v + h M^-1 f(x_m, v_m)
// Local error O(h^3), global error O(h^2).
#include "physics/cloth.hpp"

namespace weft {

// Scratch for the explicit integrators, allocated once per cloth.
struct ExplicitWorkspace {
  Positions x_start, v_start;   // state at the start of the step (3 x n)
  Positions x_mid, v_mid;       // midpoint state (3 x n)
  Positions force;              // force scratch (3 x n)
  void resize(int num_vertices);
};

void midpoint_step(Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace);

}  // namespace weft
