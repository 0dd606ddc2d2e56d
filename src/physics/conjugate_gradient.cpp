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

double ConjugateGradientSolver::dot(const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
  const int n = static_cast<int>(u.size() / 3);
  return chunked_sum(n, partials_, [&](int begin, int end) {
    return u.segment(3 * begin, 3 * (end - begin)).dot(v.segment(3 * begin, 3 * (end - begin)));
  });
}

double ConjugateGradientSolver::step_along_direction(double alpha, Eigen::VectorXd& x) {
  const int n = static_cast<int>(x.size() / 3);
  return chunked_sum(n, partials_, [&](int begin, int end) {
    const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
    x.segment(first, count) += alpha * p_.segment(first, count);
    r_.segment(first, count) -= alpha * q_.segment(first, count);
    return r_.segment(first, count).squaredNorm();
  });
}

std::array<double, 2> ConjugateGradientSolver::step_and_precondition(double alpha) {
  const int n = static_cast<int>(p_.size() / 3);
  return chunked_sums(n, pair_partials_, [&](int begin, int end) {
    const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
    y_.segment(first, count) += alpha * p_.segment(first, count);
    r_.segment(first, count) -= alpha * q_.segment(first, count);
    gauss_seidel_->multiply_diagonal(begin, end, r_, z_);
    return std::array<double, 2>{r_.segment(first, count).squaredNorm(),
                                 r_.segment(first, count).dot(z_.segment(first, count))};
  });
}

void ConjugateGradientSolver::next_direction(double beta) {
  const int n = static_cast<int>(p_.size() / 3);
  for_each_chunk(n, num_chunks, [&](int begin, int end) {
    const Eigen::Index first = 3 * begin, count = 3 * (end - begin);
    p_.segment(first, count) = z_.segment(first, count) + beta * p_.segment(first, count);
  });
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
  const bool gauss_seidel = preconditioner_ == Preconditioner::symmetric_gauss_seidel;
  if (gauss_seidel) {
    if (splits_[last_split_].pattern_id() != hessian.pattern_id()) last_split_ = 1 - last_split_;
    gauss_seidel_ = &splits_[last_split_];
    gauss_seidel_->prepare(hessian);
  } else {
    compute_preconditioner(hessian);
  }
  r_ = b;
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
  if (gauss_seidel) {
    solve_gauss_seidel(dx, threshold, max_iterations, coupling, report);
    report.relative_residual /= b_norm;
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
    const double r_squared = step_along_direction(alpha, dx);
    ++report.iterations;
    r_norm = std::sqrt(r_squared);
    if (r_norm <= threshold) break;
    const double rz_next = apply_preconditioner(r_, z_);
    const double beta = rz_next / rz;
    next_direction(beta);
    rz = rz_next;
  }
  report.relative_residual = r_norm / b_norm;
  report.converged = r_norm <= threshold;
  return report;
}

// Symmetric Gauss-Seidel preconditioned CG through Eisenstat's trick. With H = L + D + U and
// H = (D + L) + (D + U) - D, the correction e solving H e = r_0 (r_ on entry) is e = (D + U)^-1 y
// where
//   C y = (D + L)^-1 r_0,  C = (D + L)^-1 H (D + U)^-1 (symmetric positive definite),
//   C p = s + (D + L)^-1 (p - D s),  s = (D + U)^-1 p:
// one backward and one forward block solve an iteration, each off-diagonal block read once. CG
// on C preconditioned by D^-1 (z = D r^) is CG on H preconditioned by M = (D + L) D^-1 (D + U).
// CG's residual r^ = (D + L)^-1 (r_0 - H e) is not H's: the stopping test is on (D + L) r^, which
// is r_0 - H e, as block Jacobi's is on its own updated residual. It costs half a product, so it
// is computed once |r^| falls below the threshold scaled by |r^_0| / |r_0|, and when it misses,
// that scaled threshold is tightened by the miss (and half again). With a coupling the system is
// A = H + C in all of this (C t joins the second solve's right-hand side) and M is still H's split.
// On return dx holds dx + e and `report` that residual's norm (not yet divided by |b|) and whether
// it met `threshold`.
void ConjugateGradientSolver::solve_gauss_seidel(Eigen::VectorXd& dx, double threshold, int max_iterations,
                                                 const Coupling* coupling, ConjugateGradientReport& report) {
  const Eigen::Index size = dx.size();
  t_.resize(size);
  y_.setZero(size);
  const double start_norm = std::sqrt(dot(r_, r_));
  gauss_seidel_->solve_lower(r_, p_);
  r_.swap(p_);  // r_ is now r^ = (D + L)^-1 r_0
  double estimate_threshold = threshold * std::sqrt(dot(r_, r_)) / start_norm;
  gauss_seidel_->multiply_diagonal(r_, z_);
  double rz = dot(r_, z_);
  p_ = z_;
  double residual = start_norm;
  bool checked = true;  // `residual` is (D + L) r^'s norm for the current r^
  // Each iteration: the product (the new direction formed inside its first solve, the curvature
  // summed at its end), then one pass for y, r, z = D r, |r|^2 and r . z: two parallel regions.
  double beta = 0.0;
  while (report.iterations < max_iterations) {
    // q = C p and the curvature p . q (after p = z + beta p but in the first iteration).
    const double curvature = report.iterations == 0
                                 ? gauss_seidel_->multiply_transformed(p_, t_, q_, coupling)
                                 : gauss_seidel_->multiply_next_direction(z_, beta, p_, t_, q_, coupling);
    if (!(curvature > 0.0)) break;  // not positive definite along p (or NaN): stop with what we have
    const double alpha = rz / curvature;
    const auto [r_squared, rz_next] = step_and_precondition(alpha);
    ++report.iterations;
    checked = false;
    if (std::sqrt(r_squared) <= estimate_threshold) {
      residual = std::sqrt(gauss_seidel_->lower_product_squared_norm(r_));
      checked = true;
      if (residual <= threshold) break;
      estimate_threshold *= 0.5 * threshold / residual;
    }
    beta = rz_next / rz;
    rz = rz_next;
  }
  if (!checked) residual = std::sqrt(gauss_seidel_->lower_product_squared_norm(r_));
  if (report.iterations > 0) {
    gauss_seidel_->solve_upper(y_, t_);
    dx += t_;
  }
  report.relative_residual = residual;
  report.converged = residual <= threshold;
}

}  // namespace weft
