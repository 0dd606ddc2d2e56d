#pragma once
// Loops over n items cut into a fixed number of contiguous chunks, the chunks shared among the
// OpenMP threads. Sums are added chunk by chunk in chunk order, so results depend on the number
// of chunks only, never on the number of threads.
#include <array>
#include <cstddef>

namespace weft {

// The number of chunks the solvers' reductions cut a vector into, whatever the thread count.
constexpr int reduction_chunks = 64;

// First item of chunk c when n items are cut into `chunks` chunks.
inline int chunk_begin(int c, int n, int chunks) {
  return static_cast<int>(static_cast<long long>(n) * c / chunks);
}

// body(begin, end) for every chunk [begin, end) of n items, in parallel.
template <class Body>
void for_each_chunk(int n, int chunks, const Body& body) {
#pragma omp parallel for schedule(static)
  for (int c = 0; c < chunks; ++c) body(chunk_begin(c, n, chunks), chunk_begin(c + 1, n, chunks));
}

// partials[c] = partial(begin, end) for every chunk c of n items, the chunks shared among the
// threads of the enclosing parallel region (a barrier at the end; serial outside one).
template <std::size_t Chunks, class Value, class Partial>
void chunk_partials(int n, std::array<Value, Chunks>& partials, const Partial& partial) {
  const int chunks = static_cast<int>(Chunks);
#pragma omp for schedule(static)
  for (int c = 0; c < chunks; ++c) partials[c] = partial(chunk_begin(c, n, chunks), chunk_begin(c + 1, n, chunks));
}

// The partial sums added in chunk order.
template <std::size_t Chunks>
double sum_in_order(const std::array<double, Chunks>& partials) {
  double sum = 0.0;
  for (const double value : partials) sum += value;
  return sum;
}

// The sum over the chunks of partial(begin, end), a partial sum over items [begin, end).
template <std::size_t Chunks, class Partial>
double chunked_sum(int n, std::array<double, Chunks>& partials, const Partial& partial) {
#pragma omp parallel
  chunk_partials(n, partials, partial);
  return sum_in_order(partials);
}

// Two sums in one pass: partial(begin, end) returns a chunk's two partial sums; each total is
// added in chunk order, as chunked_sum adds one.
template <std::size_t Chunks, class Partial>
std::array<double, 2> chunked_sums(int n, std::array<std::array<double, 2>, Chunks>& partials,
                                   const Partial& partial) {
#pragma omp parallel
  chunk_partials(n, partials, partial);
  std::array<double, 2> sums{0.0, 0.0};
  for (const std::array<double, 2>& values : partials) {
    sums[0] += values[0];
    sums[1] += values[1];
  }
  return sums;
}

}  // namespace weft
