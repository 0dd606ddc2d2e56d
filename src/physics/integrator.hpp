#pragma once
// Which time integrator advances the cloth state.
#include <string>

namespace weft {

enum class IntegratorKind {
  symplectic_euler,  // explicit, first order, conditionally stable
  midpoint_euler_cromer,  // explicit, second order, symplectic (physics/midpoint_euler_cromer.hpp)
  explicit_midpoint,      // explicit, second order Runge-Kutta (physics/explicit_midpoint.hpp)
  implicit_euler,    // backward Euler by Newton on the incremental potential (physics/implicit_euler.hpp)
  xpbd,              // implicit Euler's model by XPBD sub-steps: the fast end (physics/xpbd.hpp)
};

const char* to_string(IntegratorKind kind);
// Parses an integrator name; returns false if it is unknown.
bool integrator_from_string(const std::string& name, IntegratorKind& kind);

}  // namespace weft
