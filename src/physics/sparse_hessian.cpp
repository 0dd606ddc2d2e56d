#include "physics/sparse_hessian.hpp"

#include <algorithm>
#include <atomic>
#include <utility>

#include "core/parallel_chunks.hpp"
#include "physics/block_row_product.hpp"

namespace weft {

namespace {
std::atomic<std::uint64_t> last_pattern_id{0};
}  // namespace

void SparseHessian::begin_pattern(int num_vertices) {
  num_vertices_ = num_vertices;
  block_columns_.assign(num_vertices, {});
  for (int i = 0; i < num_vertices; ++i) block_columns_[i].push_back(i);
  stencil_sizes_.clear();
  stencil_elements_.clear();
  stencil_slots_.clear();
}

void SparseHessian::finish_pattern() {
  // Scalar CSR layout: block row a with m block columns gives 3 scalar rows of 3m entries each.
  const int n = 3 * num_vertices_;
  std::vector<int> outer(n + 1, 0);
  for (int a = 0; a < num_vertices_; ++a) {
    std::vector<int>& columns = block_columns_[a];
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    for (int r = 0; r < 3; ++r) outer[3 * a + r + 1] = outer[3 * a + r] + 3 * static_cast<int>(columns.size());
  }
  matrix_ = Matrix(n, n);
  matrix_.resizeNonZeros(outer[n]);
  std::copy(outer.begin(), outer.end(), matrix_.outerIndexPtr());
  int* inner = matrix_.innerIndexPtr();
  for (int a = 0; a < num_vertices_; ++a) {
    for (int r = 0; r < 3; ++r) {
      int position = outer[3 * a + r];
      for (int b : block_columns_[a]) {
        for (int c = 0; c < 3; ++c) inner[position++] = 3 * b + c;
      }
    }
  }
  set_zero();

  // Where each element's blocks and each vertex's diagonal block live.
  for (size_t s = 0; s < stencil_sizes_.size(); ++s) {
    const int k = stencil_sizes_[s];
    const Eigen::MatrixXi& elements = stencil_elements_[s];
    std::vector<int>& slots = stencil_slots_.emplace_back(static_cast<size_t>(elements.cols()) * k * k * 3);
    for (Eigen::Index e = 0; e < elements.cols(); ++e) {
      for (int a = 0; a < k; ++a) {
        for (int b = 0; b < k; ++b) {
          for (int r = 0; r < 3; ++r) {
            slots[((e * k + a) * k + b) * 3 + r] = block_row_start(elements(a, e), elements(b, e), r);
          }
        }
      }
    }
  }
  diagonal_slots_.resize(3 * num_vertices_);
  for (int i = 0; i < num_vertices_; ++i) {
    for (int r = 0; r < 3; ++r) diagonal_slots_[3 * i + r] = block_row_start(i, i, r);
  }
  stencil_elements_.clear();
  stencil_elements_.shrink_to_fit();
  pattern_id_ = ++last_pattern_id;
}

int SparseHessian::block_row_start(int a, int b, int r) const {
  const std::vector<int>& columns = block_columns_[a];
  const int position = static_cast<int>(std::lower_bound(columns.begin(), columns.end(), b) - columns.begin());
  return matrix_.outerIndexPtr()[3 * a + r] + 3 * position;
}

void SparseHessian::swap(SparseHessian& other) {
  std::swap(num_vertices_, other.num_vertices_);
  std::swap(pattern_id_, other.pattern_id_);
  block_columns_.swap(other.block_columns_);
  stencil_sizes_.swap(other.stencil_sizes_);
  stencil_elements_.swap(other.stencil_elements_);
  stencil_slots_.swap(other.stencil_slots_);
  diagonal_slots_.swap(other.diagonal_slots_);
  fixed_value_indices_.swap(other.fixed_value_indices_);
  fixed_diagonal_indices_.swap(other.fixed_diagonal_indices_);
  matrix_.swap(other.matrix_);
}

void SparseHessian::set_fixed_vertices(const std::vector<char>& fixed) {
  fixed_value_indices_.clear();
  fixed_diagonal_indices_.clear();
  const int* outer = matrix_.outerIndexPtr();
  const int* inner = matrix_.innerIndexPtr();
  for (int row = 0; row < matrix_.rows(); ++row) {
    const bool row_fixed = fixed[row / 3] != 0;
    for (int k = outer[row]; k < outer[row + 1]; ++k) {
      if (row_fixed || fixed[inner[k] / 3] != 0) fixed_value_indices_.push_back(k);
      if (row_fixed && inner[k] == row) fixed_diagonal_indices_.push_back(k);
    }
  }
}

void SparseHessian::add_vertex_block(int vertex, const Mat3& block) {
  double* values = matrix_.valuePtr();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) values[diagonal_slots_[3 * vertex + r] + c] += block(r, c);
  }
}

bool SparseHessian::add_block_pair(int a, int b, const Mat3& block) {
  // One search in each block row (the pattern is symmetric): block (a, b) is the position_ab-th
  // of row a, block (b, a) the position_ba-th of row b.
  const std::vector<int>& columns_a = block_columns_[a];
  const auto found = std::lower_bound(columns_a.begin(), columns_a.end(), b);
  if (found == columns_a.end() || *found != b) return false;
  const std::vector<int>& columns_b = block_columns_[b];
  const int position_ab = static_cast<int>(found - columns_a.begin());
  const int position_ba =
      static_cast<int>(std::lower_bound(columns_b.begin(), columns_b.end(), a) - columns_b.begin());
  const int* starts = matrix_.outerIndexPtr();
  double* values = matrix_.valuePtr();
  for (int r = 0; r < 3; ++r) {
    double* ab = values + starts[3 * a + r] + 3 * position_ab;
    double* ba = values + starts[3 * b + r] + 3 * position_ba;
    for (int c = 0; c < 3; ++c) {
      ab[c] += block(r, c);
      ba[c] += block(c, r);
    }
  }
  return true;
}

void SparseHessian::set_zero() {
  double* values = matrix_.valuePtr();
  for_each_chunk(static_cast<int>(matrix_.nonZeros()), 64,
                 [&](int begin, int end) { std::fill(values + begin, values + end, 0.0); });
}

void SparseHessian::add_diagonal(double scale, const Eigen::VectorXd& diagonal) {
  double* values = matrix_.valuePtr();
#pragma omp parallel for schedule(static)
  for (int i = 0; i < num_vertices_; ++i) {
    for (int r = 0; r < 3; ++r) values[diagonal_slots_[3 * i + r] + r] += scale * diagonal[i];
  }
}

void SparseHessian::finish_assembly() {
  double* values = matrix_.valuePtr();
  for (int k : fixed_value_indices_) values[k] = 0.0;
  for (int k : fixed_diagonal_indices_) values[k] = 1.0;
}

void SparseHessian::zero_block_rows(const std::vector<int>& vertices) {
  const int* starts = matrix_.outerIndexPtr();
  double* values = matrix_.valuePtr();
  for (const int a : vertices) std::fill(values + starts[3 * a], values + starts[3 * a + 3], 0.0);
}

void SparseHessian::multiply_region(const std::vector<int>& rows, const std::vector<int>& local,
                                    const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int* starts = matrix_.outerIndexPtr();
  const int* columns = matrix_.innerIndexPtr();
  const double* values = matrix_.valuePtr();
  const double* in = x.data();
  // Block row a's three scalar rows hold `width` entries each, its blocks' columns 3b, 3b+1, 3b+2.
  for (size_t k = 0; k < rows.size(); ++k) {
    const int begin = starts[3 * rows[k]];
    const int width = starts[3 * rows[k] + 1] - begin;
    const auto entries = [&](int j) -> const double* {
      const int b = local[columns[begin + 3 * j] / 3];
      return b >= 0 ? in + 3 * b : nullptr;
    };
    block_row_product(values + begin, width / 3, 3, width, entries, y.data() + 3 * k);
  }
}

void SparseHessian::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  // Layout (finish_pattern): block row a is scalar rows 3a..3a+2 of equal length, each listing
  // its blocks' columns 3b, 3b+1, 3b+2 in the same order.
  const int* starts = matrix_.outerIndexPtr();
  const int* columns = matrix_.innerIndexPtr();
  const double* values = matrix_.valuePtr();
  const double* in = x.data();
  double* out = y.data();
#pragma omp parallel for schedule(static)
  for (int a = 0; a < num_vertices_; ++a) {
    const int begin = starts[3 * a];
    const int width = starts[3 * a + 1] - begin;
    const int* row_columns = columns + begin;
    block_row_product(
        values + begin, width / 3, 3, width, [&](int j) -> const double* { return in + row_columns[3 * j]; },
        out + 3 * a);
  }
}

}  // namespace weft
