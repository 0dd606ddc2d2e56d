#include <gtest/gtest.h>

#include <random>

#include <Eigen/Eigenvalues>

#include "physics/solve_contact.hpp"
#include "physics/sparse_hessian.hpp"

namespace weft {
namespace {

// Six vertices, one triangle (0, 1, 2): the pattern holds blocks among 0-2 and the diagonal.
SparseHessian triangle_pattern() {
  SparseHessian hessian;
  hessian.begin_pattern(6);
  Eigen::Matrix<int, 3, Eigen::Dynamic> triangle(3, 1);
  triangle << 0, 1, 2;
  hessian.add_stencil<3>(triangle);
  hessian.finish_pattern();
  hessian.set_zero();
  return hessian;
}

TEST(SparseHessian, AddsABlockPairOnlyWhereThePatternHoldsIt) {
  SparseHessian hessian = triangle_pattern();
  Mat3 block;
  block << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  EXPECT_TRUE(hessian.add_block_pair(0, 2, block));
  EXPECT_FALSE(hessian.add_block_pair(1, 4, block));
  const Eigen::MatrixXd dense = Eigen::MatrixXd(hessian.matrix());
  const Mat3 upper = dense.block(0, 6, 3, 3), lower = dense.block(6, 0, 3, 3);
  EXPECT_EQ(upper, block);
  EXPECT_EQ(lower, Mat3(block.transpose()));
  EXPECT_EQ(dense.cwiseAbs().sum(), 2.0 * block.cwiseAbs().sum());  // nothing else written
}

TEST(ContactBlocks, MatrixAndCouplingProductTogetherAreTheWholeContactHessian) {
  // One contact within the triangle (0, 1, 2), one joining 1 and 4 (off the pattern) with a
  // vertex of another mesh (-1), one on 5 alone; vertex 3 pinned.
  ContactBlocks contacts;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto psd = [&] {
    Mat3 a;
    for (int i = 0; i < 9; ++i) a.data()[i] = uniform(random);
    return Mat3(a * a.transpose());
  };
  contacts.vertices = {{0, 1, 2, -1}, {1, -1, 4, 3}, {5, -1, -1, -1}};
  contacts.weights = {{1.0, -0.2, -0.8, 0.0}, {0.3, 0.7, -1.0, 0.5}, {1.0, 0.0, 0.0, 0.0}};
  contacts.blocks = {psd(), psd(), psd()};
  SparseHessian hessian = triangle_pattern();
  ASSERT_TRUE(contacts.assemble(hessian));
  EXPECT_EQ(contacts.off_pattern.size(), 3u);  // the second contact's (1, 4), (1, 3) and (4, 3)
  Eigen::VectorXd free = Eigen::VectorXd::Ones(18);
  free.segment<3>(9).setZero();
  // The reference: every block w_j w_k K between the contact's free vertices.
  Eigen::MatrixXd reference = Eigen::MatrixXd::Zero(18, 18);
  for (size_t c = 0; c < contacts.blocks.size(); ++c) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) {
        const int a = contacts.vertices[c][j], b = contacts.vertices[c][k];
        if (a < 0 || b < 0 || free[3 * a] == 0.0 || free[3 * b] == 0.0) continue;
        reference.block<3, 3>(3 * a, 3 * b) +=
            contacts.weights[c][j] * contacts.weights[c][k] * contacts.blocks[c];
      }
    }
  }
  std::vector<char> fixed(6, 0);
  fixed[3] = 1;
  hessian.set_fixed_vertices(fixed);
  hessian.finish_assembly();
  Eigen::VectorXd p(18);
  for (int i = 0; i < 18; ++i) p[i] = uniform(random);
  p.segment<3>(9).setZero();
  Eigen::VectorXd y(18);
  hessian.multiply(p, y);
  contacts.add_coupling_product(free, p, y);
  y.segment<3>(9).setZero();  // the pinned vertex's identity row
  EXPECT_LT((y - reference * p).norm(), 1e-12 * (reference * p).norm());
}

TEST(ContactBlocks, BoundedOffPatternBlocksLeaveThePositiveSemidefiniteMatrixAboveTheContactHessian) {
  // Triangles (0, 1, 2) and (2, 3, 4), and an edge-edge contact between edge (1, 2) and edge
  // (3, 5): the pattern holds its blocks (1, 2) and (2, 3) but not (1, 3), so the in-pattern part
  // of (w w^T) (x) K alone is indefinite. Bounded, the matrix is PSD and at least the whole
  // contact Hessian.
  const auto two_triangles = [] {
    SparseHessian hessian;
    hessian.begin_pattern(6);
    Eigen::Matrix<int, 3, Eigen::Dynamic> triangles(3, 2);
    triangles << 0, 2, 1, 3, 2, 4;
    hessian.add_stencil<3>(triangles);
    hessian.finish_pattern();
    hessian.set_zero();
    return hessian;
  };
  const Vec3 n = Vec3(0.2, -0.5, 1.0).normalized();
  ContactBlocks contacts;
  contacts.vertices = {{1, 2, 3, 5}};
  contacts.weights = {{0.6, 0.4, -0.7, -0.3}};
  contacts.blocks = {n * n.transpose()};
  Eigen::MatrixXd whole = Eigen::MatrixXd::Zero(18, 18);
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) {
      whole.block<3, 3>(3 * contacts.vertices[0][j], 3 * contacts.vertices[0][k]) +=
          contacts.weights[0][j] * contacts.weights[0][k] * contacts.blocks[0];
    }
  }
  const auto smallest_eigenvalue = [](const Eigen::MatrixXd& m) {
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues()(0);
  };
  SparseHessian unbounded = two_triangles();
  ASSERT_TRUE(contacts.assemble(unbounded));
  unbounded.finish_assembly();
  EXPECT_LT(smallest_eigenvalue(Eigen::MatrixXd(unbounded.matrix())),
            -1e-2);  // what a direct solver would see

  SparseHessian bounded = two_triangles();
  EXPECT_FALSE(contacts.assemble(bounded, /*bound_off_pattern=*/true));
  EXPECT_TRUE(contacts.off_pattern.empty());
  bounded.finish_assembly();
  const Eigen::MatrixXd matrix = Eigen::MatrixXd(bounded.matrix());
  EXPECT_GT(smallest_eigenvalue(matrix), -1e-12);
  EXPECT_GT(smallest_eigenvalue(matrix - whole), -1e-12);
  EXPECT_LT((matrix - matrix.transpose()).norm(), 1e-15);
}

}  // namespace
}  // namespace weft
