#pragma once
// Projection of a symmetric element Hessian onto the positive semi-definite cone, for Newton
// steps on the incremental potential (physics/implicit_euler.hpp): H = V max(L, 0) V^T.
#include <Eigen/Core>

namespace weft {

// Replaces the symmetric matrix `m` by its nearest (Frobenius) positive semi-definite matrix:
// eigen-decomposes it and clamps negative eigenvalues to zero. Only the lower triangle is read.
// Fast path: a matrix that passes a Cholesky test with the shift 1e-12 tr(m) is left as it is
// (its smallest eigenvalue is then above -1e-12 tr(m), i.e. it is PSD to round-off). No heap
// allocation. Instantiated for N = 3, 6, 9, 12.
template <int N>
void project_to_psd(Eigen::Matrix<double, N, N>& m);

}  // namespace weft
