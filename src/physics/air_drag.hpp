#pragma once
// Air drag and wind on a triangle. With the relative velocity u = (v0 + v1 + v2)/3 - wind, unit
// normal n and area A, each vertex receives
//   f = -(1/3) A (normal_coefficient (u.n) n + tangential_coefficient (u - (u.n) n)),
// linear drag resisting the flow through the triangle and, weakly, along it. Not a potential.
#include "core/math.hpp"

namespace weft {

// Writes the force on (x0, x1, x2) stacked in `force` (zero for a zero-area triangle). When
// `velocity_jacobian` is not null, fills df/dv (9 x 9): every 3 x 3 block is
//   -(A/9) (normal_coefficient n n^T + tangential_coefficient (I - n n^T)),
// exact in the velocities and symmetric negative semi-definite for non-negative coefficients.
// n and A depend on positions only; that dependence (df/dx) is lagged, i.e. not provided.
void air_drag_forces(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                     const Vec3& wind, double normal_coefficient, double tangential_coefficient, Vector9d& force,
                     Matrix9d* velocity_jacobian);

}  // namespace weft
