#pragma once
// Triangle membrane: St. Venant-Kirchhoff in plane stress on the 3x2 deformation gradient
// F = [x1 - x0, x2 - x0] Dm^-1, with a softer response in compression (buckling) and a plastic
// rest-shape update. Energy, gradient and exact Hessian per triangle; force = -gradient.
#include <vector>

#include "core/math.hpp"
#include "physics/element_coloring.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

struct MembraneMaterial {
  double young_modulus = 1e5;       // Pa
  double poisson_ratio = 0.3;       // in [0, 0.5)
  double thickness = 5e-4;          // m
  double compression_factor = 1.0;  // in (0, 1]: stiffness kept in compression (1 = plain StVK)
  // In [0, 1): the principal stretch below which compression is resisted at the full stiffness
  // again (a triangle cannot be flattened cheaply); 0: off.
  double min_stretch = 0.0;
};

// Rest shape of one triangle, in its own 2D frame.
struct MembraneRest {
  Eigen::Matrix2d dm_inverse;  // inverse of the rest edge matrix [X1 - X0, X2 - X0] (1/m)
  double area;                 // rest area (m^2)
};

// Rest shape of (x0, x1, x2): Dm = [[|e1|, e2.e1/|e1|], [0, 2A/|e1|]] with e1 = x1 - x0,
// e2 = x2 - x0. Throws std::invalid_argument when the area is zero (to round-off) or not finite.
MembraneRest membrane_rest(const Vec3& x0, const Vec3& x1, const Vec3& x2);

// Green strain E = (F^T F - I)/2 in the rest frame.
Eigen::Matrix2d green_strain(const Vec3& x0, const Vec3& x1, const Vec3& x2, const MembraneRest& rest);

// The larger principal value of a Green strain (symmetric), in closed form.
double largest_principal_strain(const Eigen::Matrix2d& strain);

// Elastic energy rest.area * thickness * psi(E) with, for compression factor c,
//   psi = mu (tr(E+^2) + c tr(E-^2)) + lambda/2 (tr(E)+^2 + c tr(E)-^2),
// E+ / E- the positive / negative parts of E (principal strains split at zero), t+ = max(t, 0),
// t- = min(t, 0), mu = Y/(2(1 + nu)), lambda = Y nu/(1 - nu^2) (plane stress). With min_stretch
// s0 > 0, a principal strain e below e0 = (s0^2 - 1)/2 adds mu (1 - c)(e - e0)^2. psi is C1 in E;
// its second derivative jumps (by the factor c) where a principal strain or tr(E) crosses 0.
// Fills the gradient (x0, x1, x2 stacked) and the exact Hessian when they are not null.
//
// With `psd` the Hessian is made positive semi-definite instead, without an eigen-solve of the
// 9x9: it is l^T C l + (w^T S w) (x) I3, a material part (C = d2psi/dE2 is PSD because psi is a
// convex function of E) plus a geometric part that is PSD exactly when the stress S is; `psd`
// clamps S's negative principal value to zero. Where the triangle is stretched in both
// directions nothing changes, so Newton keeps its quadratic convergence there.
double membrane_energy(const Vec3& x0, const Vec3& x1, const Vec3& x2, const MembraneRest& rest,
                       const MembraneMaterial& material, Vector9d* gradient, Matrix9d* hessian,
                       bool psd = false);

// Plastic flow. With principal Green strains e_i (directions v_i in the rest frame), when
// max |e_i| > yield_strain the rest metric moves towards the current one so that each excess
// shrinks by flow_fraction: the new strain is t_i = sign(e_i) (yield + (1 - flow)(|e_i| - yield))
// where |e_i| > yield, t_i = e_i elsewhere. The new rest edges are U Dm with
//   U = sum_i rho_i v_i v_i^T,  rho_i^2 = (1 + 2 e_i)/(1 + 2 t_i),
// so dm_inverse <- dm_inverse U^-1 and area <- area rho_1 rho_2 (the triangle's mass must not be
// recomputed from the new area). Thickness is kept. Returns true when the rest shape changed
// (never for flow_fraction = 0 or a collapsed triangle, 1 + 2 e_min <= 1e-12). Requires
// yield_strain >= 0 and flow_fraction in [0, 1] (std::invalid_argument otherwise).
bool apply_plastic_yield(const Vec3& x0, const Vec3& x1, const Vec3& x2, MembraneRest& rest,
                         double yield_strain, double flow_fraction);

// The membrane term of a cloth: one rest shape per triangle (empty: the term is off).
struct MembraneTerm {
  MembraneMaterial material;
  std::vector<MembraneRest> rest;  // per triangle (n_triangles)
  double yield_strain = 0.0;       // principal Green strain beyond which the rest shape flows
  double plastic_flow = 0.0;       // fraction of the excess strain absorbed per step (0: elastic)
  ElementColoring coloring;        // of the triangles, for the parallel evaluation (none: serial)
  bool enabled() const { return !rest.empty(); }
  bool plastic() const { return plastic_flow > 0.0; }
};

// Rest shapes of every triangle; throws std::invalid_argument naming the first degenerate one.
MembraneTerm make_membrane_term(const Triangles& triangles, const Positions& rest_positions,
                                const MembraneMaterial& material, double yield_strain, double plastic_flow);

// Membrane energy of all triangles; adds the gradient and the (PSD-projected if asked) Hessian
// (stencil `stencil` over the triangles) to the outputs that are not null.
double evaluate_membrane(const MembraneTerm& term, const Triangles& triangles, const Positions& x,
                         Positions* gradient, SparseHessian* hessian, int stencil, bool project);

// Plastic flow of every triangle at x (apply_plastic_yield); returns how many yielded.
int apply_membrane_plasticity(MembraneTerm& term, const Triangles& triangles, const Positions& x);

}  // namespace weft
