#include <gtest/gtest.h>

#include <random>

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

}  // namespace
}  // namespace weft
