// The supernodal Cholesky factorisation against Eigen's dense one, on block patterns like a
// cloth's Hessian: a grid with two-ring coupling (springs and hinges) and a random graph.
#include "physics/supernodal_cholesky.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace weft {
namespace {

using Sparse = SupernodalCholesky::Matrix;

// A symmetric 3n x 3n matrix with full 3x3 blocks on the vertex pairs `edges` and on the
// diagonal: random off-diagonal blocks, diagonal blocks `diagonal` * I plus random symmetric.
Sparse block_matrix(int n, const std::vector<std::pair<int, int>>& edges, double diagonal,
                    std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int v = 0; v < n; ++v) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b <= a; ++b) {
        const double value = (a == b ? diagonal : 0.0) + uniform(rng);
        entries.emplace_back(3 * v + a, 3 * v + b, value);
        if (a != b) entries.emplace_back(3 * v + b, 3 * v + a, value);
      }
    }
  }
  for (const auto& [v, w] : edges) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        const double value = uniform(rng);
        entries.emplace_back(3 * v + a, 3 * w + b, value);
        entries.emplace_back(3 * w + b, 3 * v + a, value);
      }
    }
  }
  Sparse matrix(3 * n, 3 * n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

// Vertex pairs of an nx x ny grid coupled like a spring cloth: neighbours, diagonals, and
// vertices two apart (bend springs).
std::vector<std::pair<int, int>> grid_edges(int nx, int ny) {
  std::vector<std::pair<int, int>> edges;
  const int offsets[][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}, {2, 0}, {0, 2}};
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      for (const auto& offset : offsets) {
        const int i2 = i + offset[0], j2 = j + offset[1];
        if (i2 < nx && j2 >= 0 && j2 < ny) edges.emplace_back(j * nx + i, j2 * nx + i2);
      }
    }
  }
  return edges;
}

void expect_solves_like_dense(const Sparse& matrix, SupernodalCholesky& cholesky) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd b(matrix.rows());
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = uniform(rng);
  ASSERT_TRUE(cholesky.factorize(matrix));
  Eigen::VectorXd x;
  cholesky.solve(b, x);
  const Eigen::MatrixXd dense(matrix);
  const Eigen::VectorXd expected = dense.llt().solve(b);
  EXPECT_LT((x - expected).norm(), 1e-10 * expected.norm());
  EXPECT_LT((dense * x - b).norm(), 1e-12 * b.norm());
}

TEST(SupernodalCholesky, SolvesAGridWithTwoRingCouplingLikeDenseCholesky) {
  std::mt19937 rng(1);
  // Diagonal 40: the 18 neighbour blocks of entries in [-1, 1] keep the matrix diagonally dominant.
  const Sparse matrix = block_matrix(12 * 9, grid_edges(12, 9), 40.0, rng);
  SupernodalCholesky cholesky;
  cholesky.analyze(matrix);
  EXPECT_LT(cholesky.num_supernodes(), 12 * 9);  // columns were grouped
  expect_solves_like_dense(matrix, cholesky);
}

TEST(SupernodalCholesky, SolvesARandomGraphAndRefactorsNewValues) {
  std::mt19937 rng(2);
  const int n = 150;
  std::uniform_int_distribution<int> vertex(0, n - 1);
  std::vector<std::pair<int, int>> edges;
  for (int e = 0; e < 3 * n; ++e) {
    const int v = vertex(rng), w = vertex(rng);
    if (v != w) edges.emplace_back(std::min(v, w), std::max(v, w));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Sparse matrix = block_matrix(n, edges, 0.0, rng);
  // Make it strictly diagonally dominant whatever the degrees: diagonal = row sum of |entries| + 1.
  for (int row = 0; row < matrix.rows(); ++row) {
    double off = 0.0;
    for (Sparse::InnerIterator it(matrix, row); it; ++it) off += it.col() == row ? 0.0 : std::abs(it.value());
    matrix.coeffRef(row, row) = off + 1.0;
  }
  SupernodalCholesky cholesky;
  cholesky.analyze(matrix);
  expect_solves_like_dense(matrix, cholesky);
  // Same pattern, new values: factorize() again without a new analysis.
  for (int k = 0; k < matrix.nonZeros(); ++k) matrix.valuePtr()[k] *= 2.0;
  expect_solves_like_dense(matrix, cholesky);
}

TEST(SupernodalCholesky, ReportsAnIndefiniteMatrix) {
  std::mt19937 rng(3);
  Sparse matrix = block_matrix(10 * 10, grid_edges(10, 10), 40.0, rng);
  SupernodalCholesky cholesky;
  cholesky.analyze(matrix);
  ASSERT_TRUE(cholesky.factorize(matrix));
  // One negative diagonal entry, anywhere in the elimination order, makes it indefinite.
  for (int row : {0, 151, 299}) {
    Sparse indefinite = matrix;
    indefinite.coeffRef(row, row) = -40.0;
    EXPECT_FALSE(cholesky.factorize(indefinite)) << "row " << row;
  }
  EXPECT_TRUE(cholesky.factorize(matrix));
}

}  // namespace
}  // namespace weft
