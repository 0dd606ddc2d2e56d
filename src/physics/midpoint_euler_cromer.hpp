#pragma once
// Midpoint Euler-Cromer, the second-order form of semi-implicit Euler that Volino, Courchesne &
// Magnenat-Thalmann 1995 integrate with: the velocity is taken at the half step
// and the positions advance with it,
//   v_half = v + h/2 M^-1 f(x, v)
//   x'     = x + h v_half
//   v'     = v_half + h/2 M^-1 f(x', v_half)
// (kick, drift, kick: velocity Verlet / leapfrog). Second order; symplectic for forces from a
// potential, so an undamped oscillation keeps a bounded energy error and never grows; stable for
// w h < 2 on a mode of frequency w (the step's amplification matrix has |trace| < 2), the same
// bound as symplectic Euler's at twice the order. Two force evaluations a step (damping makes the
// end-of-step force depend on the velocity, so it is not reused).
#include "physics/cloth.hpp"
#include "physics/explicit_midpoint.hpp"

namespace weft {

void midpoint_euler_cromer_step(Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace);

}  // namespace weft
