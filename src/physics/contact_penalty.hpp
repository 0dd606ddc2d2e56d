#pragma once
// Contact penalty: the contacts the collision phase found at the start of a step, as a one-sided
// quadratic energy inside implicit Euler's incremental potential, so that Newton's solution
// already keeps layers apart instead of pushing them together for the collision response to
// undo (which, in a tight twist, stretches triangles many times over). Each contact is four
// weighted vertices with a normal frozen at the start of the step (the proximity stencil of
// collision/contact_impulse.hpp):
//   g(x) = n . sum_k w_k x_k + offset,   E = 1/2 kappa (delta - g)^2 if g < delta, else 0,
// with delta the thickness and offset the part of g from vertices outside the cloth (another
// cloth, a collider), held at their start-of-step positions. Gradient -kappa (delta - g) w_k n;
// Hessian blocks kappa w_j w_k n n^T (PSD: kappa (delta - g) >= 0 never enters). E is C1 with a
// piecewise-constant Hessian, so the collision response stays the guarantee of no crossing; the
// penalty only makes the solve aware of the contacts. Two sources fill it (sim/world.cpp): the
// last step's proximity pairs (collision.penalty_stiffness, kappa in N/m) and, before a step, a
// plane per cloth vertex that can reach a collider in it (collision.collider_contact_ratio,
// kappa = ratio m / h^2; CollisionPhase::collider_contacts). Each contact carries its kappa.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/math.hpp"

namespace weft {

class SparseHessian;

struct PenaltyContact {
  std::array<int, 4> vertices;  // vertex of the cloth, or -1 for one outside it (its part is in offset)
  std::array<double, 4> weights;
  Vec3 normal;                  // unit; g grows as the contact opens
  double offset = 0.0;          // m
  double thickness = 0.0;       // m, delta
  double stiffness = 0.0;       // N/m, kappa
};

struct ContactPenalty {
  std::vector<PenaltyContact> contacts;

  bool active() const { return !contacts.empty(); }

  // After the contacts are set: whether any joins two or more vertices of the cloth (only such
  // contacts have off-diagonal Hessian blocks), and each vertex's contacts for vertex_energy.
  // Allocates only to grow.
  void index_vertices(int num_vertices);
  // (True also when the contacts changed since index_vertices.)
  bool coupled() const { return coupled_ || indexed_ != contacts.size(); }
  // The energy of vertex v's contacts that hold no other vertex of the cloth, at x; adds their
  // gradient and Hessian block at v when not null. For the Newton tail (physics/newton_tail.hpp),
  // which runs only when nothing is coupled.
  double vertex_energy(int v, const Positions& x, Vec3* gradient, Mat3* hessian) const;

  // Energy at x; adds its gradient to `gradient` and its diagonal 3x3 blocks to `hessian` (when
  // not null). The off-diagonal blocks stay out of the sparse pattern (contacts change every
  // step): add_coupling_product applies them.
  double evaluate(const Positions& x, Positions* gradient, SparseHessian* hessian) const;

  // y += (off-diagonal blocks of the penalty Hessian at x) p, skipping vertices where `free` is 0
  // (their rows and columns are identity in the Newton system). p and y are 3n vectors.
  void add_coupling_product(const Positions& x, const Eigen::VectorXd& free, const Eigen::VectorXd& p,
                            Eigen::VectorXd& y) const;

 private:
  bool coupled_ = false;
  size_t indexed_ = 0;                // contacts.size() at index_vertices
  std::vector<int> vertex_start_;     // (n_vertices + 1) offsets into vertex_contacts_
  std::vector<int> vertex_contacts_;  // contacts of one cloth vertex, grouped by vertex
};

}  // namespace weft
