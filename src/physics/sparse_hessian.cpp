#include "physics/sparse_hessian.hpp"

#include <algorithm>
#include <atomic>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/parallel_chunks.hpp"

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

namespace {

// y[0..2] = block row a times x: the row's three scalar rows start at row0 and hold `width`
// entries each, their block columns listed at `columns` (every third entry); `entries(c)` gives
// x's three entries for scalar column c = 3b, or nullptr for a block left out.
template <class Entries>
void block_row_product(const double* row0, int width, const int* columns, Entries&& entries, double* y) {
  const double* row1 = row0 + width;
  const double* row2 = row1 + width;
#if defined(__SSE2__)
  // Columns 0 and 1 of each block row in one 16-byte load (as are x's first two entries), column
  // 2 apart: 9 loads a block instead of 13, which is what bounds this loop.
  __m128d v0 = _mm_setzero_pd(), v1 = _mm_setzero_pd(), v2 = _mm_setzero_pd();
  double y0 = 0.0, y1 = 0.0, y2 = 0.0;
  for (int k = 0; k < width; k += 3) {
    const double* xb = entries(columns[k]);
    if (xb == nullptr) continue;
    const __m128d x01 = _mm_loadu_pd(xb);
    const double x2 = xb[2];
    v0 = _mm_add_pd(v0, _mm_mul_pd(_mm_loadu_pd(row0 + k), x01));
    v1 = _mm_add_pd(v1, _mm_mul_pd(_mm_loadu_pd(row1 + k), x01));
    v2 = _mm_add_pd(v2, _mm_mul_pd(_mm_loadu_pd(row2 + k), x01));
    y0 += row0[k + 2] * x2;
    y1 += row1[k + 2] * x2;
    y2 += row2[k + 2] * x2;
  }
  double lanes[6];
  _mm_storeu_pd(lanes, v0);
  _mm_storeu_pd(lanes + 2, v1);
  _mm_storeu_pd(lanes + 4, v2);
  y[0] = (lanes[0] + lanes[1]) + y0;
  y[1] = (lanes[2] + lanes[3]) + y1;
  y[2] = (lanes[4] + lanes[5]) + y2;
#else
  // The same sums in the same order as the SSE2 path.
  double s0[3] = {0.0, 0.0, 0.0}, s1[3] = {0.0, 0.0, 0.0}, s2[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < width; k += 3) {
    const double* xb = entries(columns[k]);
    if (xb == nullptr) continue;
    for (int c = 0; c < 3; ++c) {
      s0[c] += row0[k + c] * xb[c];
      s1[c] += row1[k + c] * xb[c];
      s2[c] += row2[k + c] * xb[c];
    }
  }
  y[0] = (s0[0] + s0[1]) + s0[2];
  y[1] = (s1[0] + s1[1]) + s1[2];
  y[2] = (s2[0] + s2[1]) + s2[2];
#endif
}

}  // namespace

void SparseHessian::multiply_region(const std::vector<int>& rows, const std::vector<int>& local,
                                    const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int* starts = matrix_.outerIndexPtr();
  const int* columns = matrix_.innerIndexPtr();
  const double* values = matrix_.valuePtr();
  const double* in = x.data();
  const auto entries = [&](int column) -> const double* {
    const int b = local[column / 3];
    return b >= 0 ? in + 3 * b : nullptr;
  };
  for (size_t k = 0; k < rows.size(); ++k) {
    const int begin = starts[3 * rows[k]];
    block_row_product(values + begin, starts[3 * rows[k] + 1] - begin, columns + begin, entries,
                      y.data() + 3 * k);
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
  const auto entries = [&](int column) -> const double* { return in + column; };
#pragma omp parallel for schedule(static)
  for (int a = 0; a < num_vertices_; ++a) {
    const int begin = starts[3 * a];
    block_row_product(values + begin, starts[3 * a + 1] - begin, columns + begin, entries, out + 3 * a);
  }
}

}  // namespace weft
