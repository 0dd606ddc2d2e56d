#pragma once
// The 3n x 3n Hessian of a cloth's energy, assembled element by element into a sparsity pattern
// built once: each element stores where its 3x3 blocks live in the value array, so a step only
// zeroes and adds values (no allocation, no search). Fixed (pinned) vertices become identity
// rows and columns, so the Newton system only moves free vertices.
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "core/math.hpp"

namespace weft {

class SparseHessian {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

  // Pattern building: the diagonal blocks of all vertices are always present.
  void begin_pattern(int num_vertices);
  // Registers elements of K vertices each (K x n_elements indices); returns the stencil's id.
  // Every block between two vertices of an element is in the pattern.
  template <int K>
  int add_stencil(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements);
  void finish_pattern();

  // Vertices whose rows and columns become identity at finish_assembly().
  void set_fixed_vertices(const std::vector<char>& fixed);

  // Exchanges patterns and values with `other` without allocating (std::swap would copy the
  // Eigen 3.4 sparse matrix, which has no move constructor).
  void swap(SparseHessian& other);

  // Zeroes every value (over the OpenMP threads: megabytes at N = 64, once a Newton iteration).
  void set_zero();
  // Adds an element's (3K x 3K) matrix; element `e` of stencil `stencil`.
  template <int K>
  void add_element(int stencil, int e, const Eigen::Matrix<double, 3 * K, 3 * K>& element_matrix);
  // Adds the rank-one element matrix scale * a a^T (a of 3K entries: a Gauss-Newton term's) without
  // forming it.
  template <int K>
  void add_element_outer(int stencil, int e, double scale, const Eigen::Matrix<double, 3 * K, 1>& a);
  // Adds the element matrix whose 3x3 block (a, b) is coefficients(a, b) * I3 (a quadratic form of
  // the positions that acts alike on x, y and z) without forming it.
  template <int K>
  void add_element_isotropic(int stencil, int e, const Eigen::Matrix<double, K, K>& coefficients);
  // Adds `block` to the diagonal block of `vertex`.
  void add_vertex_block(int vertex, const Mat3& block);
  // Adds `block` to block (a, b) and its transpose to block (b, a) where the pattern holds them
  // (vertices of a common element); returns false, adding nothing, where it does not.
  bool add_block_pair(int a, int b, const Mat3& block);
  // Adds scale * diagonal[i] * I3 to the diagonal block of every vertex i.
  void add_diagonal(double scale, const Eigen::VectorXd& diagonal);
  // Makes fixed rows and columns identity.
  void finish_assembly();

  // The 3x3 diagonal block of `vertex` (after finish_assembly(): identity for fixed vertices).
  Mat3 diagonal_block(int vertex) const {
    Mat3 block;
    const double* values = matrix_.valuePtr();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) block(r, c) = values[diagonal_slots_[3 * vertex + r] + c];
    }
    return block;
  }

  // y = H x (y sized by the caller), block row by block row: each 3x3 block's column index is
  // read once and its three rows multiply the same three entries of x. Block rows are shared
  // among the OpenMP threads; each row sums in the same order whatever their number.
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;

  // Zeroes the block rows of `vertices` (a region's rows before its elements are added again).
  void zero_block_rows(const std::vector<int>& vertices);
  // y = H_RR x for a region R: for each k, block row rows[k] times x, over the block columns b
  // with local[b] >= 0 (the others are held); x and y are indexed by region position
  // (3 local[b] + c), sized 3 rows.size() at least. Serial.
  void multiply_region(const std::vector<int>& rows, const std::vector<int>& local, const Eigen::VectorXd& x,
                       Eigen::VectorXd& y) const;

  const Matrix& matrix() const { return matrix_; }
  int num_vertices() const { return num_vertices_; }
  // Different for every pattern finish_pattern() has built in this process (0 before the first), so
  // that what is derived from a pattern (physics/multicolor_gauss_seidel.hpp) knows when to redo it.
  std::uint64_t pattern_id() const { return pattern_id_; }

 private:
  // Value index of the first of the three columns of block (a, b) in scalar row 3a + r.
  int block_row_start(int a, int b, int r) const;

  int num_vertices_ = 0;
  std::uint64_t pattern_id_ = 0;
  std::vector<std::vector<int>> block_columns_;  // during pattern building: block columns per block row
  std::vector<int> stencil_sizes_;               // K of each stencil
  std::vector<Eigen::MatrixXi> stencil_elements_;
  std::vector<std::vector<int>> stencil_slots_;  // per stencil: (n_elements x K x K x 3) value offsets
  std::vector<int> diagonal_slots_;              // per vertex: 3 offsets of its diagonal block rows
  std::vector<int> fixed_value_indices_;         // values to zero for fixed rows and columns
  std::vector<int> fixed_diagonal_indices_;      // values set to one
  Matrix matrix_;
};

template <int K>
int SparseHessian::add_stencil(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements) {
  for (Eigen::Index e = 0; e < elements.cols(); ++e) {
    for (int a = 0; a < K; ++a) {
      for (int b = 0; b < K; ++b) block_columns_[elements(a, e)].push_back(elements(b, e));
    }
  }
  stencil_sizes_.push_back(K);
  stencil_elements_.push_back(elements);
  return static_cast<int>(stencil_sizes_.size()) - 1;
}

template <int K>
void SparseHessian::add_element(int stencil, int e, const Eigen::Matrix<double, 3 * K, 3 * K>& element_matrix) {
  const int* slots = stencil_slots_[stencil].data() + static_cast<size_t>(e) * K * K * 3;
  double* values = matrix_.valuePtr();
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K; ++b) {
      for (int r = 0; r < 3; ++r) {
        double* row = values + slots[(a * K + b) * 3 + r];
        for (int c = 0; c < 3; ++c) row[c] += element_matrix(3 * a + r, 3 * b + c);
      }
    }
  }
}

template <int K>
void SparseHessian::add_element_outer(int stencil, int e, double scale, const Eigen::Matrix<double, 3 * K, 1>& a) {
  const int* slots = stencil_slots_[stencil].data() + static_cast<size_t>(e) * K * K * 3;
  double* values = matrix_.valuePtr();
  for (int p = 0; p < K; ++p) {
    const Vec3 scaled = scale * a.template segment<3>(3 * p);
    for (int q = 0; q < K; ++q) {
      const Vec3 column = a.template segment<3>(3 * q);
      for (int r = 0; r < 3; ++r) {
        double* row = values + slots[(p * K + q) * 3 + r];
        for (int c = 0; c < 3; ++c) row[c] += scaled[r] * column[c];
      }
    }
  }
}

template <int K>
void SparseHessian::add_element_isotropic(int stencil, int e, const Eigen::Matrix<double, K, K>& coefficients) {
  const int* slots = stencil_slots_[stencil].data() + static_cast<size_t>(e) * K * K * 3;
  double* values = matrix_.valuePtr();
  for (int a = 0; a < K; ++a) {
    for (int b = 0; b < K; ++b) {
      for (int r = 0; r < 3; ++r) values[slots[(a * K + b) * 3 + r] + r] += coefficients(a, b);
    }
  }
}

}  // namespace weft
