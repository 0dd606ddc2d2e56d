#pragma once
// Contact as implicit Euler's Newton solve sees it (collision.response "barrier"): an energy of
// the cloth's positions (barrier and lagged friction, physics/contact_barrier.hpp), and, for each
// Newton direction, the largest step along it that keeps every pair apart. The solver takes no
// step beyond that bound, so every iterate is free of intersections when the start is
// (sim/barrier_contact.hpp implements it over the world's meshes).
#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/math.hpp"

namespace weft {

class SparseHessian;

// The contact Hessian as blocks: contact c joins up to four cloth vertices (-1: a vertex of
// another mesh, held fixed in this solve) with weights w, and its Hessian block between its
// vertices j and k is w_j w_k K_c (K_c symmetric PSD, so the whole is PSD).
struct ContactBlocks {
  std::vector<std::array<int, 4>> vertices;
  std::vector<std::array<double, 4>> weights;
  std::vector<Mat3> blocks;
  // assemble(): the off-diagonal blocks (contact, j, k), j < k stencil slots, whose vertices
  // share no element, so the matrix's pattern lacks them (self and cloth-cloth pairs).
  std::vector<std::array<int, 3>> off_pattern;

  void clear() {
    vertices.clear();
    weights.clear();
    blocks.clear();
    off_pattern.clear();
  }
  bool empty() const { return blocks.empty(); }
  // Adds every block w_j w_k K the pattern holds to the matrix (the diagonal ones, and those
  // between vertices of one element: a cloth edge against a collider's) and lists the rest in
  // off_pattern; returns whether there are any (then CG needs add_coupling_product).
  //
  // With `bound_off_pattern` (a direct solver, which sees the matrix alone) an off-pattern block
  // is not listed but bounded on the diagonal: |w_j w_k| K joins blocks j and k. The matrix alone
  // keeps only some of a contact's blocks, which is indefinite in general (a pair's Hessian
  // (w w^T) (x) K is PSD only whole); [a^2 + |ab|, 0; 0, b^2 + |ab|] (x) K - [a^2, ab; ab, b^2] (x) K
  // is PSD, so the bounded matrix is PSD and at least the contact Hessian.
  bool assemble(SparseHessian& hessian, bool bound_off_pattern = false);
  // y += (the off_pattern blocks) p over the vertices where `free` is 1 (3n vectors).
  void add_coupling_product(const Eigen::VectorXd& free, const Eigen::VectorXd& p, Eigen::VectorXd& y) const;
};

// What a step's contact did, for the step's stats.
struct SolveContactReport {
  int pairs = 0;                   // pairs within the contact radius at the step's end
  int vertex_face_candidates = 0;  // candidates of the step's last search
  int edge_edge_candidates = 0;
};

class SolveContact {
 public:
  virtual ~SolveContact() = default;
  // The step's start (free of intersections): finds the pairs along the predictor's motion
  // x_start -> x_start + predictor, lags friction at x_start and returns the predictor's bound
  // (as max_step does).
  virtual double begin_step(const Positions& x_start, const Positions& predictor, double h) = 0;
  // Finds the pairs that may come within the contact radius along x -> x + dx (they are the
  // ones evaluate() reads until the next call) and returns the largest fraction of dx, in
  // [0, 1], along which every pair keeps a positive distance. (dx by reference to any 3 x n
  // block, so that a Newton step held as one vector is passed without a copy.)
  virtual double max_step(const Positions& x, const Eigen::Ref<const Positions>& dx) = 0;
  // The contact energy at a point of the last max_step's segment; adds its gradient (when not
  // null) and its Hessian blocks (when not null; cleared first).
  virtual double evaluate(const Positions& x, Positions* gradient, ContactBlocks* blocks) = 0;
  // evaluate()'s part from the contacts with a cloth vertex where `moving` is nonzero (one entry
  // per cloth vertex): where only those vertices move, the rest of the energy stays as it is.
  // Leaves last_potential() and report() alone.
  virtual double evaluate_moving(const Positions& x, const std::vector<char>& moving, Positions* gradient,
                                 ContactBlocks* blocks) = 0;
  // The energy that is potential (the barrier; friction is dissipation) at the last evaluate().
  virtual double last_potential() const = 0;
  virtual const SolveContactReport& report() const = 0;
};

}  // namespace weft
