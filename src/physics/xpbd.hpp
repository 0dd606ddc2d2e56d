#pragma once
// XPBD (Macklin, Müller and Chentanez 2016) with small steps (Macklin et al. 2019): the fast end
// of the speed/accuracy trade, on the same model as implicit Euler.
//
// Every elastic element e (a spring, a membrane triangle, a hinge) with energy E_e >= 0 becomes
// the constraint C_e = sqrt(2 E_e) with compliance 1, so that E_e = C_e^2 / 2. XPBD's fixed point
// for a step of h,  M (x - x_hat) / h^2 + sum_e grad C_e C_e = 0,  is then exactly the stationary
// point of implicit Euler's incremental potential 1/(2h^2) |x - x_hat|^2_M + sum_e E_e: the same
// solution, reached by Gauss-Seidel sweeps over the elements instead of Newton. What XPBD trades
// away is how far those sweeps get; sub-steps (several short steps with one sweep each) are the
// cheap way to get further (Macklin et al. 2019).
//
// One step of h is `substeps` sub-steps of hs = h / substeps, each:
//   1. v += hs (g + M^-1 f_other(x, v)), with f_other the terms that are not constraints, taken
//      explicitly: air drag, spring damping, enclosed-volume pressure; then v /= 1 + c hs for the
//      mass damping c (implicit in v, like implicit Euler's dissipation potential);
//   2. x_prev = x; x += hs v (pinned vertices, inverse mass 0, keep their scripted velocity);
//   3. `iterations` Gauss-Seidel sweeps over springs, membrane triangles and hinges, each element
//      moving its vertices by  dx_i = w_i grad_i C dlambda,
//      dlambda = (-C - lambda / hs^2) / (sum_i w_i |grad_i C|^2 + 1 / hs^2),  lambda += dlambda;
//   4. v = (x - x_prev) / hs.
// Linear momentum is conserved by every element update (the energies are translation invariant).
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
  Eigen::VectorXd edge_rest_length_, edge_compliance_, edge_compression_compliance_;
  std::vector<double> spring_lambda_, edge_lambda_, hinge_lambda_;
  Positions x_prev_;
  Positions other_force_;  // f_other of step 1
};

}  // namespace weft
