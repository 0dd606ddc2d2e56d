#pragma once
// The inner loop of every product with 3x3 blocks: one block row times x. Shared by the
// Hessian's product (physics/sparse_hessian.cpp, blocks in the CSR's scalar rows) and the
// Gauss-Seidel solves (physics/multicolor_gauss_seidel.cpp, blocks copied 9 values each), which
// differ only in where a block's rows lie. The sums run in one fixed order, so results are the
// same bits whichever thread computes a row.
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace weft {

// y[0..2] = sum over the `count` blocks j of B_j times x's three entries for block column j.
// Block j's rows r = 0, 1, 2 hold its three columns at blocks + j * block_step + r * row_step;
// entries(j) gives x's three entries for block j, or nullptr for a block left out.
template <class Entries>
inline void block_row_product(const double* blocks, int count, int block_step, int row_step,
                              Entries&& entries, double* y) {
  const double* row0 = blocks;
  const double* row1 = blocks + row_step;
  const double* row2 = blocks + 2 * row_step;
#if defined(__SSE2__)
  // Columns 0 and 1 of each block row in one 16-byte load (as are x's first two entries), column
  // 2 apart: 9 loads a block instead of 13, which is what bounds this loop.
  __m128d v0 = _mm_setzero_pd(), v1 = _mm_setzero_pd(), v2 = _mm_setzero_pd();
  double y0 = 0.0, y1 = 0.0, y2 = 0.0;
  for (int j = 0; j < count; ++j) {
    const double* xb = entries(j);
    if (xb == nullptr) continue;
    const int k = j * block_step;
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
  for (int j = 0; j < count; ++j) {
    const double* xb = entries(j);
    if (xb == nullptr) continue;
    const int k = j * block_step;
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

}  // namespace weft
