#pragma once
// The tail of an implicit Euler step's Newton solve, restricted to where the residual is.
//
// In a contact step the last few Newton iterations have only a small share of the vertices above
// the tolerance: the residual's tail is local (docs/integrators.md, "Which linear solver inside
// implicit Euler"). A global iteration still assembles and solves the whole cloth. Here the
// region is the free vertices whose residual is above the tolerance and their neighbours; each
// iteration assembles only the elements touching it (their Hessian afresh: one kept from the
// first iteration stalls or diverges), solves the region's rows of the element-wise projected
// Hessian by conjugate gradient with everything else held, and takes an Armijo line search on
// the part of the incremental potential that the region's vertices enter. The gradient is then
// recomputed on every vertex those elements touch, so the residual the next region comes from is
// exact. The caller evaluates the whole gradient afterwards: the residual a step reports is
// always the whole cloth's.
//
// Terms: the membrane, hinges (dihedral: Gauss-Newton Hessian; quadratic: its constant exact
// one), gravity, the inertia and Rayleigh mass damping, contact penalties that hold one vertex
// each (collider contacts), and contact inside the solve (physics/solve_contact.hpp). With the
// latter, each iteration's matrix takes the contact blocks among the region's vertices, its line
// search starts at the step the contact allows along the region's move (every pair stays apart)
// and sees the energy of the contacts with a region vertex (the others do not change), and the
// gradient follows those contacts onto every vertex they join, in the region or not. supports()
// says whether a model's terms are those.
#include <vector>

#include "physics/cloth.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/contact_penalty.hpp"
#include "physics/solve_contact.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

struct NewtonTailSettings {
  double tolerance = 1e-2;      // m/s, the step's Newton tolerance
  double largest_share = 0.02;  // the tail starts when at most this share of the vertices is above
  int max_iterations = 8;
  int max_cg_iterations = 200;
  double cg_tolerance = 1e-3;  // relative to the region's gradient
};

class NewtonTail {
 public:
  // Whether every term of `model` is one the tail evaluates element by element.
  static bool supports(const ClothModel& model);
  bool collapsed() const { return collapsed_; }
  // Incidence lists and scratch for `model` (allocates; step() then does not).
  void prepare(const ClothModel& model);

  // Restricted Newton iterations from x (whose full, pin-masked gradient is `gradient`) while the
  // vertices above the tolerance number at most largest_share of the free ones; x and gradient
  // are updated in place (gradient exact wherever it changed). `hessian` is the solver's, with
  // its stencils: the region's rows are overwritten (the caller assembles afresh after).
  // Returns the iterations taken (0: not started); collapsed() then says whether it stopped on a
  // step that raised the residual a hundredfold (undone).
  // `penalty` (or null) must not be coupled(). `contact` (or null) is the step's contact, its
  // last max_step() along a segment that holds x; `contact_gradient` is then its gradient at x
  // (unmasked, part of `gradient`), kept current.
  int iterate(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
              const Positions& x_hat, const ContactPenalty* penalty, SolveContact* contact,
              const NewtonTailSettings& settings, SparseHessian& hessian, const HessianStencils& stencils,
              Positions& x, Positions& gradient, Positions* contact_gradient);

 private:
  // Counts the vertices above the tolerance and returns the count; when it is within (0, largest],
  // collects the region (those vertices plus neighbours, free only) and the elements that touch it.
  int collect_region(const ClothModel& model, double h, double tolerance, double largest,
                     const Positions& gradient);
  // The largest residual h |g_i| / m_i over the vertices the region's elements touch.
  double worst_residual(const ClothModel& model, double h, const Positions& gradient) const;
  // The part of the incremental potential that the region's vertices enter.
  double region_potential(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                          const Positions& x_hat, const Positions& x) const;
  // The Hessian's block rows of the region at x (projected membrane, Gauss-Newton hinges, inertia
  // and damping, and the contact's blocks among the region's vertices: those on the diagonal in
  // the matrix, the others in coupling_) and the inverses of their diagonal blocks.
  void assemble_region(const ClothModel& model, double h, const Positions& x, SparseHessian& hessian,
                       const HessianStencils& stencils);
  // Recomputes the gradient of every vertex of the region's elements.
  void update_gradient(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                       const Positions& x_hat, const Positions& x, Positions& gradient);
  // With contact: the change of the region's contacts' gradient since partial_gradient_ joins
  // contact_gradient and `gradient` (the touched vertices, just recomputed without contact, take
  // contact_gradient whole); partial_gradient_ is then x's.
  void update_contact_gradient(const ClothModel& model, const Positions& x, Positions& gradient,
                               Positions& contact_gradient);
  Vec3 vertex_gradient(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                       const Positions& x_hat, const Positions& x, int i) const;
  // The contact's blocks (contact_blocks_) on the region's diagonal and in coupling_.
  void add_contact_blocks(SparseHessian& hessian);
  // Region CG on the assembled rows; dx_ gets the step. Returns false if no descent direction.
  bool solve(const ClothModel& model, double h, const SparseHessian& hessian,
             const NewtonTailSettings& settings);

  int num_vertices_ = 0;
  // Incidence, CSR: the triangles and hinges of each vertex, and its neighbours.
  std::vector<int> triangle_starts_, triangle_list_, hinge_starts_, hinge_list_, neighbour_starts_,
      neighbour_list_;
  // The region: vertices, each one's position in it (-1: outside), its elements, and the
  // vertices those elements touch.
  std::vector<int> region_, local_, region_triangles_, region_hinges_, touched_;
  std::vector<char> triangle_mark_, hinge_mark_, touched_mark_;
  Eigen::VectorXd region_gradient_, dx_, r_, z_, p_, q_;
  std::vector<Mat3> inverse_blocks_;
  Positions saved_;  // the region's positions before a line search (3 x n, region columns used)
  const ContactPenalty* penalty_ = nullptr;  // iterate's, while it runs
  SolveContact* contact_ = nullptr;          // iterate's, while it runs
  // The contact's blocks at the region's iterate, and those joining two region vertices
  // (local indices, the block w_j w_k K): off the diagonal, in the region CG's product.
  struct Coupling {
    int a, b;
    Mat3 block;
  };
  ContactBlocks contact_blocks_;
  std::vector<Coupling> coupling_;
  Positions step_;  // the region's move as a whole-cloth segment (3 x n, zero outside)
  // The contact's gradient from the contacts with a region vertex (evaluate_moving) at the
  // current iterate, and at the next.
  Positions partial_gradient_, new_partial_gradient_;
  std::vector<char> moving_;  // 1 for the region's vertices
  bool collapsed_ = false;
};

}  // namespace weft
