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
// one), gravity, the inertia and Rayleigh mass damping, and contact penalties that hold one
// vertex each (collider contacts). supports() says whether a model holds only those.
#include <vector>

#include "physics/cloth.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/contact_penalty.hpp"
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
  // `penalty` (or null) must not be coupled().
  int iterate(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
              const Positions& x_hat, const ContactPenalty* penalty, const NewtonTailSettings& settings,
              SparseHessian& hessian, const HessianStencils& stencils, Positions& x, Positions& gradient);

 private:
  // Counts the vertices above the tolerance and returns the count; when it is within (0, largest],
  // collects the region (those vertices plus neighbours, free only) and the elements that touch it.
  int collect_region(const ClothModel& model, double h, double tolerance, double largest, const Positions& gradient);
  // The largest residual h |g_i| / m_i over the vertices the region's elements touch.
  double worst_residual(const ClothModel& model, double h, const Positions& gradient) const;
  // The part of the incremental potential that the region's vertices enter.
  double region_potential(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                          const Positions& x_hat, const Positions& x) const;
  // The Hessian's block rows of the region at x (projected membrane, Gauss-Newton hinges, inertia
  // and damping) and the inverses of their diagonal blocks.
  void assemble_region(const ClothModel& model, double h, const Positions& x, SparseHessian& hessian,
                       const HessianStencils& stencils);
  // Recomputes the gradient of every vertex of the region's elements.
  void update_gradient(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                       const Positions& x_hat, const Positions& x, Positions& gradient);
  Vec3 vertex_gradient(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                       const Positions& x_hat, const Positions& x, int i) const;
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
  bool collapsed_ = false;
};

}  // namespace weft
