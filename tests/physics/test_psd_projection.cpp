// PSD projection: the result is V max(L, 0) V^T, has no negative eigenvalue beyond round-off,
// leaves PSD matrices as they are and is idempotent.
#include "physics/psd_projection.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "core/math.hpp"

namespace weft {
namespace {

template <int N>
Eigen::Matrix<double, N, N> random_symmetric(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, N> a;
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) a(i, j) = normal(rng);
  }
  return a + a.transpose();
}

template <int N>
void check_projection(unsigned seed) {
  using Matrix = Eigen::Matrix<double, N, N>;
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 10; ++trial) {
    const Matrix original = random_symmetric<N>(rng);
    Matrix projected = original;
    project_to_psd(projected);

    // Reference: clamp the spectrum with a dynamic-size solver.
    const Eigen::MatrixXd dynamic = original;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> reference(dynamic);
    const Eigen::MatrixXd expected = reference.eigenvectors() *
                                     reference.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                     reference.eigenvectors().transpose();
    EXPECT_LE((projected - expected).norm(), 1e-12 * original.norm());
    EXPECT_EQ(projected, projected.transpose());

    const Eigen::SelfAdjointEigenSolver<Matrix> eigen(projected);
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * eigen.eigenvalues().maxCoeff());

    Matrix again = projected;
    project_to_psd(again);
    EXPECT_LE((again - projected).norm(), 1e-12 * projected.norm());
  }
}

TEST(PsdProjection, ClampsNegativeEigenvaluesSize6) { check_projection<6>(1); }
TEST(PsdProjection, ClampsNegativeEigenvaluesSize9) { check_projection<9>(2); }
TEST(PsdProjection, ClampsNegativeEigenvaluesSize12) { check_projection<12>(3); }

TEST(PsdProjection, LeavesPsdMatricesUnchanged) {
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, 12, 6> b;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 6; ++j) b(i, j) = normal(rng);
  }
  // Positive definite: returned exactly as it was (fast path).
  const Matrix12d definite = b * b.transpose() + Matrix12d::Identity();
  Matrix12d m = definite;
  project_to_psd(m);
  EXPECT_EQ(m, definite);
  // Semi-definite of rank 6: unchanged to round-off.
  const Matrix12d semi_definite = b * b.transpose();
  m = semi_definite;
  project_to_psd(m);
  EXPECT_LE((m - semi_definite).norm(), 1e-12 * semi_definite.norm());
}

TEST(PsdProjection, NegativeDefiniteBecomesZero) {
  Matrix9d m = -Matrix9d::Identity();
  m(0, 1) = m(1, 0) = 0.3;
  project_to_psd(m);
  EXPECT_LE(m.norm(), 1e-15);
}

}  // namespace
}  // namespace weft
