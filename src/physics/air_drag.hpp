#pragma once
// Air drag and wind on a triangle. With the relative velocity u = (v0 + v1 + v2)/3 - wind, unit
// normal n and area A, each vertex receives
//   f = -(1/3) A (normal_coefficient (u.n) n + tangential_coefficient (u - (u.n) n)),
// linear drag resisting the flow through the triangle and, weakly, along it. Not a potential.
#include "core/math.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

// The drag matrix D = normal_coefficient n n^T + tangential_coefficient (I - n n^T) of the
// triangle; returns its area (0, and D = 0, for a zero-area triangle).
double air_drag_matrix(const Vec3& x0, const Vec3& x1, const Vec3& x2, double normal_coefficient,
                       double tangential_coefficient, Mat3& drag);

// Writes the force on (x0, x1, x2) stacked in `force` (zero for a zero-area triangle). When
// `velocity_jacobian` is not null, fills df/dv (9 x 9): every 3 x 3 block is
//   -(A/9) (normal_coefficient n n^T + tangential_coefficient (I - n n^T)),
// exact in the velocities and symmetric negative semi-definite for non-negative coefficients.
// n and A depend on positions only; that dependence (df/dx) is lagged, i.e. not provided.
void air_drag_forces(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& v0, const Vec3& v1, const Vec3& v2,
                     const Vec3& wind, double normal_coefficient, double tangential_coefficient, Vector9d& force,
                     Matrix9d* velocity_jacobian);

// The air-drag term of a cloth (both coefficients 0: off). Coefficients in kg/(m^2 s): force per
// unit area per unit relative velocity.
struct AirDragTerm {
  double normal_coefficient = 0.0;
  double tangential_coefficient = 0.0;
  Vec3 wind = Vec3::Zero();  // m/s, the air's velocity
  bool enabled() const { return normal_coefficient > 0.0 || tangential_coefficient > 0.0; }
};

// Adds the drag force of every triangle at (x, v) to `force`.
void add_air_drag_forces(const AirDragTerm& term, const Triangles& triangles, const Positions& x, const Positions& v,
                         Positions& force);

// Drag as a dissipation potential for implicit Euler over a step of h from x_start, normals and
// areas lagged at x_start: P(x) = h sum_t A/2 (u - w)^T D (u - w), u = mean of (x - x_start)/h over
// the triangle's vertices. Its gradient is minus the drag force at v = (x - x_start)/h; its
// Hessian has the PSD blocks A D/(9h). Adds both to the outputs that are not null.
double evaluate_air_drag_dissipation(const AirDragTerm& term, const Triangles& triangles, const Positions& x_start,
                                     const Positions& x, double h, Positions* gradient, SparseHessian* hessian,
                                     int stencil);

}  // namespace weft
