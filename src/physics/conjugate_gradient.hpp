#pragma once
// Preconditioned conjugate gradient for the Newton system H dx = b of implicit Euler, with a
// block-Jacobi preconditioner: the inverse of each vertex's 3x3 diagonal block of H. Against the
// scalar (diagonal) Jacobi preconditioner it keeps the coupling between a vertex's x, y and z,
// which a stretched membrane makes strong. Buffers are sized once; a solve allocates nothing.
// The vector work is fused into three passes an iteration over OpenMP threads, with reductions
// summed over a fixed number of chunks in order: the same bits on any number of threads.
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "physics/sparse_hessian.hpp"

namespace weft {

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
  using Coupling = std::function<void(const Eigen::VectorXd&, Eigen::VectorXd&)>;
  ConjugateGradientReport solve(const SparseHessian& hessian, const Eigen::VectorXd& b, Eigen::VectorXd& dx,
                                double tolerance, int max_iterations, const Coupling* coupling = nullptr,
                                const Eigen::VectorXd* guess = nullptr);

 private:
  void compute_preconditioner(const SparseHessian& hessian);
  double apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z);

  std::vector<Mat3> inverse_blocks_;
  // Vectors are cut into this many chunks of whole vertices whatever the thread count; each
  // reduction sums its chunks' partial sums in chunk order.
  static constexpr int num_chunks = 64;
  std::array<double, num_chunks> partials_{};
  Eigen::VectorXd r_, z_, p_, q_;
};

}  // namespace weft
