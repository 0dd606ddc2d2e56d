#include "physics/psd_projection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace weft {

template <int N>
void project_to_psd(Eigen::Matrix<double, N, N>& m) {
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;

  // Already PSD to round-off: m + shift I is positive definite.
  const double trace = m.trace();
  if (trace > 0.0) {
    Matrix shifted = m;
    shifted.diagonal().array() += 1e-12 * trace;
    Eigen::LLT<Matrix> cholesky(shifted);
    if (cholesky.info() == Eigen::Success) return;
  }

  // m = V L V^T  ->  V max(L, 0) V^T = m + sum over negative L_i of w_i w_i^T, w_i = sqrt(-L_i) v_i
  // (usually few terms). Mirrored from the lower triangle first: the result is exactly symmetric.
  const Eigen::SelfAdjointEigenSolver<Matrix> eigen(m);
  const Vector& values = eigen.eigenvalues();  // ascending
  m.template triangularView<Eigen::StrictlyUpper>() = m.transpose();
  for (int i = 0; i < N && values[i] < 0.0; ++i) {
    const Vector w = std::sqrt(-values[i]) * eigen.eigenvectors().col(i);
    m.noalias() += w * w.transpose();
  }
}

template void project_to_psd<3>(Eigen::Matrix<double, 3, 3>&);
template void project_to_psd<6>(Eigen::Matrix<double, 6, 6>&);
template void project_to_psd<9>(Eigen::Matrix<double, 9, 9>&);
template void project_to_psd<12>(Eigen::Matrix<double, 12, 12>&);

}  // namespace weft
