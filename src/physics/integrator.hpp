#pragma once
// Which time integrator advances the cloth state.

namespace weft {

enum class IntegratorKind {
  symplectic_euler,  // explicit, first order, conditionally stable
  midpoint_euler_cromer,  // explicit, second order, symplectic (physics/midpoint_euler_cromer.hpp)
  explicit_midpoint,      // explicit, second order Runge-Kutta (physics/explicit_midpoint.hpp)
  implicit_euler,    // backward Euler by Newton on the incremental potential (physics/implicit_euler.hpp)
  xpbd,              // implicit Euler's model by XPBD sub-steps: the fast end (physics/xpbd.hpp)
};

const char* to_string(IntegratorKind kind);

}  // namespace weft
