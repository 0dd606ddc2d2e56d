#include "physics/conjugate_gradient.hpp"

#include <cmath>

namespace weft {

void ConjugateGradientSolver::compute_preconditioner(const SparseHessian& hessian) {
  const int n = hessian.num_vertices();
  inverse_blocks_.resize(n);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    // Each block is symmetric positive definite: the mass term alone is (m_i / h^2) I.
    inverse_blocks_[i] = hessian.diagonal_block(i).inverse();
  }
}

void ConjugateGradientSolver::apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const int n = static_cast<int>(inverse_blocks_.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) z.segment<3>(3 * i).noalias() = inverse_blocks_[i] * r.segment<3>(3 * i);
}

ConjugateGradientReport ConjugateGradientSolver::solve(const SparseHessian& hessian, const Eigen::VectorXd& b,
                                                       Eigen::VectorXd& dx, double tolerance, int max_iterations,
                                                       const Coupling* coupling) {
  const SparseHessian::Matrix& matrix = hessian.matrix();
  const Eigen::Index size = matrix.rows();
  r_.resize(size);
  z_.resize(size);
  p_.resize(size);
  q_.resize(size);
  dx.setZero(size);
  ConjugateGradientReport report;
  const double b_norm = b.norm();
  if (b_norm == 0.0) {
    report.converged = true;
    return report;
  }
  compute_preconditioner(hessian);
  r_ = b;
  apply_preconditioner(r_, z_);
  p_ = z_;
  double rz = r_.dot(z_);
  const double threshold = tolerance * b_norm;
  double r_norm = b_norm;
  while (report.iterations < max_iterations) {
    hessian.multiply(p_, q_);
    if (coupling != nullptr) (*coupling)(p_, q_);
    const double curvature = p_.dot(q_);
    if (!(curvature > 0.0)) break;  // not positive definite along p (or NaN): stop with what we have
    const double alpha = rz / curvature;
    dx.noalias() += alpha * p_;
    r_.noalias() -= alpha * q_;
    ++report.iterations;
    r_norm = r_.norm();
    if (r_norm <= threshold) break;
    apply_preconditioner(r_, z_);
    const double rz_next = r_.dot(z_);
    p_ = z_ + (rz_next / rz) * p_;
    rz = rz_next;
  }
  report.relative_residual = r_norm / b_norm;
  report.converged = r_norm <= threshold;
  return report;
}

}  // namespace weft
