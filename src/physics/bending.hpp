#pragma once
// The bending term of a cloth: one energy per interior edge (hinge) of the rest mesh, in one of two
// models with the same stiffness (J) and the same small-angle energy:
// - dihedral (hinge_bending.hpp): stiffness * weight * (theta - rest_angle)^2, any rest shape;
// - quadratic (quadratic_bending.hpp): stiffness * scale * |sum_i w_i x_i|^2, flat rest shapes
//   only; a constant, exact, PSD Hessian and no 1/height singularity as a wing collapses.
// Dihedral is the default: the quadratic model's restoring moment 2 k w sin(theta) fades past 90
// degrees, so creases fold shut more readily and the collision response then stretches triangles
// (docs/scenes.md, "bending"). Scenes whose solves stall on collapsing wings ask for quadratic
// (the twists and the tumble dryer).
#include <vector>

#include "core/math.hpp"
#include "core/topology.hpp"
#include "physics/element_coloring.hpp"
#include "physics/hinge_bending.hpp"
#include "physics/quadratic_bending.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

enum class BendingModel { dihedral, quadratic };

// A hinge counts as flat at rest when its dihedral angle is within this of zero (rad). The
// quadratic model treats such a hinge as exactly flat: its rest energy, stiffness * weight *
// 4 sin^2(theta/2), is below 1e-6 of the stiffness times the weight.
constexpr double flat_rest_angle = 1e-3;

struct BendingTerm {
  BendingModel model = BendingModel::dihedral;
  Eigen::Matrix4Xi hinges;                  // MeshTopology::hinges layout (4 x n_hinges)
  std::vector<HingeRest> rest;              // per hinge, dihedral model
  std::vector<QuadraticHinge> quadratic;    // per hinge, quadratic model
  double stiffness = 0.0;                   // J (N m)
  ElementColoring coloring;                 // of the hinges, for the parallel evaluation (none: serial)
  bool enabled() const { return hinges.cols() > 0; }
};

// Hinges and their rest data from the rest mesh; hinges with a degenerate wing are left out.
// Throws std::invalid_argument if `model` is quadratic and a hinge is not flat at rest (the message
// names the largest rest angle).
BendingTerm make_bending_term(const MeshTopology& topology, const Positions& rest_positions, double stiffness,
                              BendingModel model);

// Bending energy of hinge h alone; fills its gradient (x0..x3 stacked) when not null, and adds its
// Hessian to `hessian` (stencil `stencil`, projected as evaluate_bending says) when not null.
double bending_element_energy(const BendingTerm& term, int h, const Positions& x, Vector12d* gradient,
                              SparseHessian* hessian = nullptr, int stencil = 0, bool project = false);

// Bending energy of all hinges; adds the gradient and the Hessian (stencil `stencil` over
// term.hinges) to the outputs that are not null. The quadratic model's Hessian is exact and PSD
// whether or not `project` is set. For the dihedral model, `project` makes each hinge's Hessian PSD
// by its Gauss-Newton part rather than by an eigen-decomposition: a 12x12 eigen-projection per
// hinge is a large share of an implicit step, the Gauss-Newton form costs a rank-one update, and
// Newton converges in as many iterations. That rank-one matrix is added block by block
// (SparseHessian::add_element_outer), never formed. Since theta is invariant under rigid motion,
// a . u = 0 for every rigid velocity u, so the Gauss-Newton matrix leaves rigid motion free. No PSD
// matrix that leaves the wing tips uncoupled can do so and still resist bending (a rotation about
// the hinge edge moves each tip along its own a-part), which is why the tips' blocks stay in the
// pattern.
double evaluate_bending(const BendingTerm& term, const Positions& x, Positions* gradient, SparseHessian* hessian,
                        int stencil, bool project);

// How stiff the dihedral hinges are against the cloth's inertia (1/s^2): the largest, over the
// free vertices (inverse_mass > 0), of the trace of the hinges' Gauss-Newton blocks on a vertex's
// diagonal in the rest shape, sum over its hinges of curvature |grad_v theta|^2, over its mass.
// Times h^2 it is the share those blocks add to implicit Euler's m/h^2 on that vertex
// (ImplicitEulerSettings::bending_hessian_share; docs/integrators.md, "Which linear solver inside
// implicit Euler"). It grows as h^2 / edge^4. Infinite for the quadratic model (its exact Hessian
// is always kept).
double bending_stiffness_rate(const BendingTerm& term, const Positions& rest_positions,
                              const Eigen::VectorXd& inverse_mass);

const char* to_string(BendingModel model);

}  // namespace weft
