#include "physics/multicolor_gauss_seidel.hpp"

#include <algorithm>

#include "core/parallel_chunks.hpp"
#include "physics/block_row_product.hpp"

namespace weft {

namespace {

// The sum over `count` blocks (9 entries each, row by row, at `blocks`) of block j times x's three
// entries at columns[j].
inline Vec3 block_row_sum(const double* blocks, const int* columns, int count, const double* x) {
  Vec3 sum;
  block_row_product(
      blocks, count, 9, 3, [&](int j) { return x + columns[j]; }, sum.data());
  return sum;
}

// Blocks of the Hessian before the one whose first value is at `offset` in block row a: each
// block holds 9 values, and block row a's first is at starts[3 a].
inline int block_index(const int* starts, int a, int offset) {
  return starts[3 * a] / 9 + (offset - starts[3 * a]) / 3;
}

}  // namespace

// Greedy colouring in vertex order (each vertex takes the smallest colour none of its block
// neighbours has), then each row's off-diagonal blocks split by colour into lower and upper.
void MulticolorGaussSeidel::analyse_pattern(const SparseHessian& hessian) {
  const int n = hessian.num_vertices();
  const SparseHessian::Matrix& matrix = hessian.matrix();
  const int* starts = matrix.outerIndexPtr();
  const int* columns = matrix.innerIndexPtr();
  const auto for_each_neighbour = [&](int a, const auto& body) {
    for (int k = starts[3 * a]; k < starts[3 * a + 1]; k += 3) {
      const int b = columns[k] / 3;
      if (b != a) body(b, k);
    }
  };

  std::vector<int> color(n, -1);
  std::vector<char> taken;
  int num_colors = 0;
  for (int a = 0; a < n; ++a) {
    taken.assign(num_colors + 1, 0);
    for_each_neighbour(a, [&](int b, int) {
      if (color[b] >= 0) taken[color[b]] = 1;
    });
    color[a] = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    num_colors = std::max(num_colors, color[a] + 1);
  }

  color_starts_.assign(num_colors + 1, 0);
  for (int a = 0; a < n; ++a) ++color_starts_[color[a] + 1];
  for (int c = 0; c < num_colors; ++c) color_starts_[c + 1] += color_starts_[c];
  order_.resize(n);
  std::vector<int> next(color_starts_.begin(), color_starts_.end() - 1);
  for (int a = 0; a < n; ++a) order_[next[color[a]]++] = a;

  // Each row's lower and upper blocks in colour order; where each block of the Hessian goes.
  lower_starts_.assign(1, 0);
  upper_starts_.assign(1, 0);
  lower_columns_.clear();
  upper_columns_.clear();
  destinations_.assign(matrix.nonZeros() / 9, -1);
  for (int k = 0; k < n; ++k) {
    const int a = order_[k];
    for_each_neighbour(a, [&](int b, int offset) {
      const bool lower = color[b] < color[a];
      std::vector<int>& list = lower ? lower_columns_ : upper_columns_;
      destinations_[block_index(starts, a, offset)] = 2 * static_cast<int>(list.size()) + (lower ? 0 : 1);
      list.push_back(3 * b);
    });
    lower_starts_.push_back(static_cast<int>(lower_columns_.size()));
    upper_starts_.push_back(static_cast<int>(upper_columns_.size()));
  }
  positions_.resize(n);
  for (int k = 0; k < n; ++k) positions_[order_[k]] = k;
  lower_values_.resize(9 * lower_columns_.size());
  upper_values_.resize(9 * upper_columns_.size());
  diagonal_.resize(n);
  inverse_diagonal_.resize(n);
  remainder_.resize(3 * n);
  solved_.resize(3 * n);
  pattern_id_ = hessian.pattern_id();
}

// One pass over the Hessian in its own order: each row's blocks copied where the solves read them.
void MulticolorGaussSeidel::prepare(const SparseHessian& hessian) {
  if (hessian.pattern_id() != pattern_id_) analyse_pattern(hessian);
  const int n = hessian.num_vertices();
  const SparseHessian::Matrix& matrix = hessian.matrix();
  const int* starts = matrix.outerIndexPtr();
  const double* values = matrix.valuePtr();
#pragma omp parallel for schedule(static)
  for (int a = 0; a < n; ++a) {
    const int begin = starts[3 * a];
    const int width = starts[3 * a + 1] - begin;
    const int* destinations = destinations_.data() + block_index(starts, a, begin);
    const int k = positions_[a];
    for (int i = 0; i < width / 3; ++i) {
      const double* source = values + begin + 3 * i;  // the block's first row; the others `width` on
      const int destination = destinations[i];
      if (destination < 0) {
        Mat3& diagonal = diagonal_[k];
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) diagonal(r, c) = source[r * width + c];
        }
        inverse_diagonal_[k] = diagonal.inverse();
        continue;
      }
      double* block =
          (destination % 2 == 0 ? lower_values_.data() : upper_values_.data()) + 9 * (destination / 2);
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) block[3 * r + c] = source[r * width + c];
      }
    }
  }
}

std::vector<int> MulticolorGaussSeidel::colors() const {
  std::vector<int> color(order_.size());
  for (int c = 0; c < num_colors(); ++c) {
    for (int k = color_starts_[c]; k < color_starts_[c + 1]; ++k) color[order_[k]] = c;
  }
  return color;
}

// Colour c's rows of a solve: out_a = D_a^-1 (rhs(k, a) - sum over the row's lower (upper)
// blocks H_ab out_b), the rows shared among the threads of the enclosing parallel region (a
// barrier at the end); then finish(k, a, out_a). `out` must not be what rhs reads.
template <bool lower, class Rhs, class Finish>
void MulticolorGaussSeidel::solve_color(int c, const Rhs& rhs, Eigen::VectorXd& out,
                                        const Finish& finish) const {
  const std::vector<int>& block_starts = lower ? lower_starts_ : upper_starts_;
  const int* columns = lower ? lower_columns_.data() : upper_columns_.data();
  const double* values = lower ? lower_values_.data() : upper_values_.data();
  const double* solved = out.data();
#pragma omp for schedule(static)
  for (int k = color_starts_[c]; k < color_starts_[c + 1]; ++k) {
    const int a = order_[k];
    const Vec3 sum = block_row_sum(values + 9 * block_starts[k], columns + block_starts[k],
                                   block_starts[k + 1] - block_starts[k], solved);
    const Vec3 value = inverse_diagonal_[k] * (rhs(k, a) - sum);
    out.segment<3>(3 * a) = value;
    finish(k, a, value);
  }
}

// The whole solve, colour by colour in order (lower) or in reverse (upper).
template <bool lower, class Rhs, class Finish>
void MulticolorGaussSeidel::solve(const Rhs& rhs, Eigen::VectorXd& out, const Finish& finish) const {
  const int colors = num_colors();
#pragma omp parallel
  for (int step = 0; step < colors; ++step)
    solve_color<lower>(lower ? step : colors - 1 - step, rhs, out, finish);
}

namespace {

// rhs(k, a) of a solve that reads v_a.
auto entries_of(const Eigen::VectorXd& v) {
  return [&v](int, int a) -> Vec3 { return v.segment<3>(3 * a); };
}

}  // namespace

void MulticolorGaussSeidel::solve_lower(const Eigen::VectorXd& w, Eigen::VectorXd& u) const {
  solve<true>(entries_of(w), u, [](int, int, const Vec3&) {});
}

void MulticolorGaussSeidel::solve_upper(const Eigen::VectorXd& v, Eigen::VectorXd& t) const {
  solve<false>(entries_of(v), t, [](int, int, const Vec3&) {});
}

// Eisenstat's product: t = (D + U)^-1 p (each row's p - D t kept), then q = t + (D + L)^-1 of
// those, both solves in one parallel region. Colour 0 has no lower blocks, so its rows of the
// second solve are finished where the first solve ends on them: one barrier fewer.
template <class Direction>
double MulticolorGaussSeidel::multiply_transformed(const Direction& direction, const Eigen::VectorXd& p,
                                                   Eigen::VectorXd& t, Eigen::VectorXd& q,
                                                   const Coupling* coupling) {
  const int colors = num_colors();
  const int n = static_cast<int>(order_.size());
  const auto finish_lower = [&](int, int a, const Vec3& u_a) {
    q.segment<3>(3 * a) = u_a + t.segment<3>(3 * a);
  };
  // With a coupling, p - D t gains C t, which needs the whole of t: colour 0's rows of the
  // second solve wait for it with the others.
  const int first_lower = coupling != nullptr ? 0 : 1;
  const auto finish_upper = [&](int k, int a, const Vec3& t_a) {
    const Vec3 remainder = p.segment<3>(3 * a) - diagonal_[k] * t_a;
    remainder_.segment<3>(3 * a) = remainder;
    if (first_lower == 1 && k < color_starts_[1]) {  // colour 0: (D + L)^-1's row is D_a^-1 alone
      const Vec3 u_a = inverse_diagonal_[k] * remainder;
      solved_.segment<3>(3 * a) = u_a;
      finish_lower(k, a, u_a);
    }
  };
  if (coupling != nullptr) {
#pragma omp parallel
    for (int c = colors - 1; c >= 0; --c) solve_color<false>(c, direction, t, finish_upper);
    (*coupling)(t, remainder_);
  }
#pragma omp parallel
  {
    if (coupling == nullptr) {
      for (int c = colors - 1; c >= 0; --c) solve_color<false>(c, direction, t, finish_upper);
    }
    for (int c = first_lower; c < colors; ++c) {
      solve_color<true>(c, entries_of(remainder_), solved_, finish_lower);
    }
    // The curvature, chunk by chunk as chunked_sum cuts and sums a dot product.
    chunk_partials(n, partials_, [&](int begin, int end) {
      return p.segment(3 * begin, 3 * (end - begin)).dot(q.segment(3 * begin, 3 * (end - begin)));
    });
  }
  return sum_in_order(partials_);
}

double MulticolorGaussSeidel::multiply_transformed(const Eigen::VectorXd& p, Eigen::VectorXd& t,
                                                   Eigen::VectorXd& q, const Coupling* coupling) {
  return multiply_transformed(entries_of(p), p, t, q, coupling);
}

double MulticolorGaussSeidel::multiply_next_direction(const Eigen::VectorXd& z, double beta,
                                                      Eigen::VectorXd& p, Eigen::VectorXd& t,
                                                      Eigen::VectorXd& q, const Coupling* coupling) {
  // Row a's entries of p are read by row a alone in the first solve, so each is updated there.
  const auto next = [&](int, int a) -> Vec3 {
    p.segment<3>(3 * a) = z.segment<3>(3 * a) + beta * p.segment<3>(3 * a);
    return p.segment<3>(3 * a);
  };
  return multiply_transformed(next, p, t, q, coupling);
}

double MulticolorGaussSeidel::lower_product_squared_norm(const Eigen::VectorXd& x) {
  const double* entries = x.data();
  return chunked_sum(static_cast<int>(order_.size()), partials_, [&](int begin, int end) {
    double sum = 0.0;
    for (int k = begin; k < end; ++k) {
      const int a = order_[k];
      const Vec3 lower =
          block_row_sum(lower_values_.data() + 9 * lower_starts_[k], lower_columns_.data() + lower_starts_[k],
                        lower_starts_[k + 1] - lower_starts_[k], entries);
      sum += (diagonal_[k] * x.segment<3>(3 * a) + lower).squaredNorm();
    }
    return sum;
  });
}

void MulticolorGaussSeidel::multiply_diagonal(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  for_each_chunk(static_cast<int>(order_.size()), reduction_chunks,
                 [&](int begin, int end) { multiply_diagonal(begin, end, x, y); });
}

void MulticolorGaussSeidel::multiply_diagonal(int begin, int end, const Eigen::VectorXd& x,
                                              Eigen::VectorXd& y) const {
  for (int a = begin; a < end; ++a) y.segment<3>(3 * a) = diagonal_[positions_[a]] * x.segment<3>(3 * a);
}

}  // namespace weft
