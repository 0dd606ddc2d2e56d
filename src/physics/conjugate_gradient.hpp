#pragma once
// Preconditioned conjugate gradient for the Newton system H dx = b of implicit Euler. Two
// preconditioners, both working on 3x3 blocks, so that the coupling between a vertex's x, y and
// z (strong in a stretched membrane) is kept: symmetric Gauss-Seidel in multicolour order (the
// default; physics/multicolor_gauss_seidel.hpp), or block Jacobi, the inverse of each vertex's
// diagonal block. Buffers are sized once; a solve allocates nothing (a new sparsity pattern
// sizes the Gauss-Seidel split once). The vector work is fused into a few passes an iteration
// over OpenMP threads, with reductions summed over a fixed number of chunks in order: the same
// bits on any number of threads.
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/parallel_chunks.hpp"
#include "physics/multicolor_gauss_seidel.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {

// Block Jacobi: z = D^-1 r with D the 3x3 diagonal blocks; cheap, parallel, many iterations.
// Symmetric Gauss-Seidel in multicolour order (physics/multicolor_gauss_seidel.hpp) through
// Eisenstat's trick: about half the iterations at about the cost of one product each. A coupling
// term (kept out of the sparse pattern) joins the product but not the preconditioner.
enum class Preconditioner { block_jacobi, symmetric_gauss_seidel };

struct ConjugateGradientReport {
  int iterations = 0;
  double relative_residual = 0.0;  // |b - H dx| / |b| at exit
  bool converged = false;          // relative_residual <= tolerance
};

class ConjugateGradientSolver {
 public:
  // Solves hessian * dx = b from dx = 0 until |b - H dx| <= tolerance |b| or max_iterations.
  // H must be symmetric positive definite (PSD-projected terms plus M / h^2). `coupling`, when
  // given, adds a part of H kept out of the sparse pattern: coupling(p, y) does y += H_extra p
  // (H_extra's diagonal blocks must already be in `hessian`, which the preconditioner reads).
  // `guess`, when given, is a direction d the solution is expected to lie close to: CG then
  // starts from the minimiser of the quadratic along d, dx = (b . d / d^T H d) d, instead of 0
  // (one product more). The implicit Euler step passes the drop gravity alone would cause, the
  // smoothest mode of the cloth and the one block Jacobi needs the most iterations to build.
  using Coupling = MulticolorGaussSeidel::Coupling;
  // Whatever the preconditioner, convergence is |b - H dx| <= tolerance |b| on the true residual.
  ConjugateGradientReport solve(const SparseHessian& hessian, const Eigen::VectorXd& b, Eigen::VectorXd& dx,
                                double tolerance, int max_iterations, const Coupling* coupling = nullptr,
                                const Eigen::VectorXd* guess = nullptr);

  void set_preconditioner(Preconditioner preconditioner) { preconditioner_ = preconditioner; }

 private:
  void compute_preconditioner(const SparseHessian& hessian);
  double apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  double dot(const Eigen::VectorXd& u, const Eigen::VectorXd& v);
  // x += alpha p, r -= alpha q in one pass; returns |r|^2.
  double step_along_direction(double alpha, Eigen::VectorXd& x);
  // p = z + beta p.
  void next_direction(double beta);
  // Symmetric Gauss-Seidel: y += alpha p, r -= alpha q and z = D r in one pass; returns |r|^2 and
  // r . z (each summed as dot() sums it).
  std::array<double, 2> step_and_precondition(double alpha);
  // CG for the correction to dx (r_ = b - H dx on entry) on Eisenstat's transformed system.
  void solve_gauss_seidel(Eigen::VectorXd& dx, double threshold, int max_iterations, const Coupling* coupling,
                          ConjugateGradientReport& report);

  Preconditioner preconditioner_ = Preconditioner::symmetric_gauss_seidel;
  // Gauss-Seidel splits of the last two patterns seen (implicit Euler alternates between the
  // matrix without the hinges and the one with them), so that alternating does not redo them.
  std::array<MulticolorGaussSeidel, 2> splits_;
  int last_split_ = 0;
  MulticolorGaussSeidel* gauss_seidel_ = nullptr;  // the split of the current solve's pattern
  std::vector<Mat3> inverse_blocks_;
  // Vectors are cut into this many chunks of whole vertices whatever the thread count; each
  // reduction sums its chunks' partial sums in chunk order.
  static constexpr int num_chunks = reduction_chunks;
  std::array<double, num_chunks> partials_{};
  std::array<std::array<double, 2>, num_chunks> pair_partials_{};
  Eigen::VectorXd r_, z_, p_, q_;
  Eigen::VectorXd t_, y_;  // symmetric Gauss-Seidel only
};

}  // namespace weft
