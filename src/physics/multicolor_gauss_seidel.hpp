#pragma once
// Symmetric Gauss-Seidel for conjugate gradient, in multicolour order. With the Hessian split
// into its 3x3 diagonal blocks D and the blocks below and above them, H = L + D + U (U = L^T), the
// preconditioner is M = (D + L) D^-1 (D + U); CG applies it through Eisenstat's trick
// (physics/conjugate_gradient.cpp), which needs only the two block triangular solves below and
// a product with D.
//
// "Below" is in an order of the vertices by colour: a greedy colouring of the block pattern, in
// which no two vertices that share a block have the same colour. The blocks of a row whose
// column has an earlier colour are L's, a later colour U's; rows of one colour do not depend on
// each other, so each colour's rows are solved in parallel (a barrier between colours), and
// each off-diagonal block is read once by the two solves together (each row's lower and upper
// blocks are listed apart), as in one product with H. Every row sums in a fixed order: the same
// bits on any number of threads.
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/math.hpp"
#include "core/parallel_chunks.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

class MulticolorGaussSeidel {
 public:
  // Colours the pattern and lists each row's lower and upper blocks when `hessian`'s pattern is
  // new (its pattern_id()), then reads its diagonal blocks and their inverses (which must exist:
  // the assembled Hessian's diagonal blocks are positive definite). No allocation once a pattern
  // has been seen.
  void prepare(const SparseHessian& hessian);

  // u = (D + L)^-1 w, colour by colour in order (u sized by the caller, not w).
  void solve_lower(const Eigen::VectorXd& w, Eigen::VectorXd& u) const;
  // t = (D + U)^-1 v, colour by colour in reverse (t not v).
  void solve_upper(const Eigen::VectorXd& v, Eigen::VectorXd& t) const;
  // A part C of the system matrix kept out of the split's pattern: coupling(v, y) does y += C v.
  // The system is then A = H + C, preconditioned by H's split alone.
  using Coupling = std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>;
  // q = C p with C = (D + L)^-1 A (D + U)^-1, as Eisenstat's trick forms it: t = (D + U)^-1 p,
  // then q = t + (D + L)^-1 (p - D t + C t) (the last term only with a coupling; A = H without).
  // Also leaves t in `t` (sized by the caller, as q). Returns the curvature p . q, summed over
  // `reduction_chunks` chunks of whole vertices in order (as CG's dot products are), in the
  // product's own parallel region.
  double multiply_transformed(const Eigen::VectorXd& p, Eigen::VectorXd& t, Eigen::VectorXd& q,
                              const Coupling* coupling = nullptr);
  // CG's next direction and its product in one: p = z + beta p, row by row as the first solve
  // reaches it (no pass of its own), then q = C p, t and p . q as above.
  double multiply_next_direction(const Eigen::VectorXd& z, double beta, Eigen::VectorXd& p,
                                 Eigen::VectorXd& t, Eigen::VectorXd& q, const Coupling* coupling = nullptr);
  // y = D x.
  void multiply_diagonal(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y_a = D_a x_a for the vertices a in [begin, end) (a piece of another pass over the vertices).
  void multiply_diagonal(int begin, int end, const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // |(D + L) x|^2, summed over a fixed number of chunks in order.
  double lower_product_squared_norm(const Eigen::VectorXd& x);

  // The pattern_id() of the Hessian the split was made for (0 before the first).
  std::uint64_t pattern_id() const { return pattern_id_; }
  int num_colors() const { return std::max(0, static_cast<int>(color_starts_.size()) - 1); }
  // The colour of each vertex (for tests).
  std::vector<int> colors() const;

 private:
  void analyse_pattern(const SparseHessian& hessian);
  // The product with the first solve's right-hand side given row by row (direction(k, a) = p_a).
  template <class Direction>
  double multiply_transformed(const Direction& direction, const Eigen::VectorXd& p, Eigen::VectorXd& t,
                              Eigen::VectorXd& q, const Coupling* coupling);
  // out_a = D_a^-1 (rhs(k, a) - sum of the row's lower (upper) blocks times out), then
  // finish(k, a, out_a) (k the position of a); rhs is called once a row, by the thread solving it.
  template <bool lower, class Rhs, class Finish>
  void solve(const Rhs& rhs, Eigen::VectorXd& out, const Finish& finish) const;
  // Colour c's rows of such a solve, inside the caller's parallel region.
  template <bool lower, class Rhs, class Finish>
  void solve_color(int c, const Rhs& rhs, Eigen::VectorXd& out, const Finish& finish) const;

  std::uint64_t pattern_id_ = 0;
  std::vector<int> order_;                        // vertices by colour, ascending within one (n)
  std::vector<int> color_starts_;                 // where each colour begins in order_ (colours + 1)
  std::vector<int> lower_starts_, upper_starts_;  // per position (n + 1): its blocks' range below
  // Off-diagonal blocks of the rows in order_, the lower ones and the upper ones apart, so that a
  // solve reads them in order: x's first entry 3 b for block column b, and the block's 9 values
  // row by row (copied there by prepare()).
  std::vector<int> lower_columns_, upper_columns_;
  // Per block of the Hessian, in its order: where prepare() copies it, 2 j for lower block j,
  // 2 j + 1 for upper block j, -1 for a diagonal block.
  std::vector<int> destinations_;
  std::vector<int> positions_;  // per vertex: its position in order_
  std::vector<double> lower_values_, upper_values_;
  std::vector<Mat3> diagonal_, inverse_diagonal_;  // per position in order_
  std::array<double, reduction_chunks> partials_{};
  Eigen::VectorXd remainder_, solved_;  // multiply_transformed's p - D t and (D + L)^-1 of it
};

}  // namespace weft
