#pragma once
// Every force term a cloth has enabled, evaluated together: the potential energy with its
// gradient and Hessian (implicit Euler), the dissipation potential of the damping terms, and
// the total force (explicit integrators). A term that is off is skipped entirely.
#include "physics/cloth.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

// Potential energy of each term, J.
struct TermEnergies {
  double springs = 0.0;
  double membrane = 0.0;
  double bending = 0.0;
  double pressure = 0.0;
  double gravity = 0.0;
  double elastic() const { return springs + membrane + bending + pressure; }
  TermEnergies& operator+=(const TermEnergies& other);
};

// Stencil ids of the terms in a SparseHessian (-1: no term uses it).
struct HessianStencils {
  int springs = -1;    // 2-vertex springs
  int triangles = -1;  // membrane, drag and pressure
  int hinges = -1;     // 4-vertex hinges
};

// Builds the Hessian's sparsity pattern for the cloth's enabled terms and its fixed vertices.
// Every element couples all its vertices, the hinges' wing tips included: leaving those blocks
// out and lumping them onto the tips' diagonal blocks would halve a CG product but stiffens
// rigid motion of the tips, so that small or fine cloths freeze in the air.
// Without `hinges_in_matrix` the hinges have no stencil (stencils.hinges = -1): their energy and
// gradient are still evaluated, their Hessian is left out of the matrix as a whole
// (ImplicitEulerSettings::bending_hessian_share says when).
void prepare_hessian(const ClothModel& model, SparseHessian& hessian, HessianStencils& stencils,
                     bool hinges_in_matrix = true);

// Potential energy E(x) (elastic terms and gravity). Adds dE/dx to `gradient` and the
// element-wise PSD-projected Hessian (if `project`) to `hessian` when they are not null (the
// terms that have a stencil in `stencils`).
double evaluate_potential(const ClothModel& model, const Vec3& gravity, const Positions& x, Positions* gradient,
                          SparseHessian* hessian, const HessianStencils& stencils, bool project,
                          TermEnergies* energies = nullptr);

// Dissipation potential of the damping terms over a step of h from x_start, whose gradient
// at x is minus the damping force at velocity (x - x_start) / h.
double evaluate_dissipation(const ClothModel& model, const Positions& x_start, const Positions& x, double h,
                            Positions* gradient, SparseHessian* hessian, const HessianStencils& stencils);

// The mass-weighted quadratic (weight / 2) |x - center|^2_M, the form of implicit Euler's inertia
// term (weight 1/h^2 around the inertial predictor) and of mass damping's dissipation (c/h around
// the step's start). Adds its gradient weight M (x - center) and Hessian weight M to those not
// null. Over the OpenMP threads in fixed chunks: the same bits on any thread count.
double evaluate_mass_quadratic(const Eigen::VectorXd& mass, double weight, const Positions& x,
                               const Positions& center, Positions* gradient, SparseHessian* hessian);

// Total force -dE/dx plus damping forces at (x, v), written to `force`.
void compute_forces(const ClothModel& model, const Vec3& gravity, const Positions& x, const Positions& v,
                    Positions& force);

}  // namespace weft
