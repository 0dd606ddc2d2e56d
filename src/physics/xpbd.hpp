#pragma once
// XPBD (Macklin, Müller and Chentanez 2016) with small steps (Macklin et al. 2019): the fast end
// of the speed/accuracy trade (docs/integrators.md has the measured trade).
//
// Constraints, each with the compliance that makes its energy the scene's:
//   - springs: C = l - L, compliance 1/k, with XPBD's implicit damping for the spring damping;
//   - membrane: one distance constraint per mesh edge with van Gelder's (1998) stiffness
//     k = E t (sum of the rest areas of the edge's triangles) / L^2, 1/compression_factor softer
//     when shorter than rest. This is edge springs, not the StVK triangle of implicit Euler;
//   - hinges: C = sqrt(2 E) of the hinge energy with compliance 1, so E = C^2 / 2 exactly.
//
// One step of h is `substeps` sub-steps of hs = h / substeps, each:
//   1. v += hs (g + M^-1 f_other(x, v)), with f_other the terms that are not constraints, taken
//      explicitly: air drag, enclosed-volume pressure, damping of springs without stiffness; then
//      v /= 1 + c hs for the mass damping c;
//   2. x_prev = x; x += hs v (pinned vertices, inverse mass 0, keep their scripted velocity);
//   3. `iterations` Gauss-Seidel sweeps over springs, membrane edges and hinges, each constraint
//      moving its vertices by  dx_i = w_i grad_i C dlambda,
//      dlambda = (-C - alpha~ lambda) / (sum_i w_i |grad_i C|^2 + alpha~),  alpha~ = alpha / hs^2;
//   4. v = (x - x_prev) / hs.
// Every update conserves linear momentum (the constraints are translation invariant). XPBD's
// fixed point is not exactly implicit Euler's step (it drops the change of grad C over the
// sweeps), and with few sweeps a stiff cloth comes out stretchier than its material.
#include <vector>

#include "physics/cloth.hpp"

namespace weft {

struct XpbdSettings {
  int substeps = 4;    // sub-steps per step of h
  int iterations = 1;  // Gauss-Seidel sweeps per sub-step
};

// Preallocated multipliers for one cloth's XPBD steps; nothing is carried between steps.
class XpbdSolver {
 public:
  // Advances the cloth by h (> 0).
  void step(Cloth& cloth, const Vec3& gravity, double h, const XpbdSettings& settings);

 private:
  void prepare(const ClothModel& model);
  void predict(const ClothModel& model, ClothState& state, const Vec3& gravity, double hs);
  void sweep(const ClothModel& model, Positions& x, double hs);

  int prepared_vertices_ = -1, prepared_triangles_ = -1;
  Eigen::Matrix2Xi edges_;  // membrane edges (2 x n_edges)
  Eigen::VectorXd edge_rest_length_, edge_area_over_length2_;  // L and sum_T A_T / L^2 at rest
  std::vector<double> spring_lambda_, edge_lambda_, hinge_lambda_;
  Positions x_prev_;
  Positions other_force_;  // f_other of step 1
};

}  // namespace weft
