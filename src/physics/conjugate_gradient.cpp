#include "physics/conjugate_gradient.hpp"

#include <array>
#include <cmath>

#include "core/parallel_chunks.hpp"

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

// z = P^-1 r (block Jacobi); returns r . z.
double ConjugateGradientSolver::apply_preconditioner(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  const int n = static_cast<int>(inverse_blocks_.size());
  return chunked_sum(n, partials_, [&](int begin, int end) {
    double rz = 0.0;
    for (int i = begin; i < end; ++i) {
      const Vec3 zi = inverse_blocks_[i] * r.segment<3>(3 * i);
      z.segment<3>(3 * i) = zi;
      rz += zi.dot(r.segment<3>(3 * i));
    }
    return rz;
  });
}

ConjugateGradientReport ConjugateGradientSolver::solve(const SparseHessian& hessian, const Eigen::VectorXd& b,
                                                       Eigen::VectorXd& dx, double tolerance, int max_iterations,
                                                       const Coupling* coupling, const Eigen::VectorXd* guess) {
  const SparseHessian::Matrix& matrix = hessian.matrix();
  const Eigen::Index size = matrix.rows();
  const int n = hessian.num_vertices();
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
  const auto dot = [&](const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
    return chunked_sum(n, partials_, [&](int begin, int end) {
      return u.segment(3 * begin, 3 * (end - begin)).dot(v.segment(3 * begin, 3 * (end - begin)));
    });
  };
  if (guess != nullptr) {
    hessian.multiply(*guess, q_);
    if (coupling != nullptr) (*coupling)(*guess, q_);
    const double curvature = dot(*guess, q_);
    const double along = dot(b, *guess);
    if (curvature > 0.0 && std::isfinite(along)) {
      const double alpha = along / curvature;
      for_each_chunk(n, num_chunks, [&](int begin, int end) {
        const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
        dx.segment(first, count) = alpha * guess->segment(first, count);
        r_.segment(first, count) -= alpha * q_.segment(first, count);
      });
    }
  }
  double r_norm = std::sqrt(dot(r_, r_));
  const double threshold = tolerance * b_norm;
  if (r_norm <= threshold) {
    report.relative_residual = r_norm / b_norm;
    report.converged = true;
    return report;
  }
  double rz = apply_preconditioner(r_, z_);
  p_ = z_;
  // Each iteration: the product, then three fused passes over the vectors (curvature; dx, r and
  // |r|^2; z and r . z) and the new direction.
  while (report.iterations < max_iterations) {
    hessian.multiply(p_, q_);
    if (coupling != nullptr) (*coupling)(p_, q_);
    const double curvature = dot(p_, q_);
    if (!(curvature > 0.0)) break;  // not positive definite along p (or NaN): stop with what we have
    const double alpha = rz / curvature;
    const double r_squared = chunked_sum(n, partials_, [&](int begin, int end) {
      const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
      dx.segment(first, count) += alpha * p_.segment(first, count);
      r_.segment(first, count) -= alpha * q_.segment(first, count);
      return r_.segment(first, count).squaredNorm();
    });
    ++report.iterations;
    r_norm = std::sqrt(r_squared);
    if (r_norm <= threshold) break;
    const double rz_next = apply_preconditioner(r_, z_);
    const double beta = rz_next / rz;
    for_each_chunk(n, num_chunks, [&](int begin, int end) {
      const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
      p_.segment(first, count) = z_.segment(first, count) + beta * p_.segment(first, count);
    });
    rz = rz_next;
  }
  report.relative_residual = r_norm / b_norm;
  report.converged = r_norm <= threshold;
  return report;
}

}  // namespace weft
