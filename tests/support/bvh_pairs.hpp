#pragma once
// Triangle pairs whose boxes overlap, listed through the hierarchy walk the broad phase uses
// (collision/bvh_traversal.hpp): what the BVH tests compare against brute force, to check the
// tree, its refits and the walk. The simulator queries primitive pairs instead
// (collision/primitive_queries.hpp).
#include <omp.h>

#include <algorithm>
#include <vector>

#include "collision/bvh.hpp"
#include "collision/bvh_traversal.hpp"
#include "core/topology.hpp"

namespace weft::testing {

// Whether a self listing keeps the pairs of triangles that share a vertex.
enum class SharedVertexPairs { skip, keep };

namespace detail {

template <bool self>
std::vector<TrianglePair> overlapping_pairs(const Bvh& first, const Bvh& second, bool keep_neighbours,
                                            const char* culled) {
  const int num_threads = std::max(1, omp_get_max_threads());
  std::vector<std::vector<TrianglePair>> found(static_cast<size_t>(num_threads));
  const Triangles& triangles = first.triangles();
  auto collect = [&](int thread, int s, int t) {
    if (self && !keep_neighbours && share_vertex(triangles, s, t)) return;
    found[thread].push_back(self ? TrianglePair{std::min(s, t), std::max(s, t)} : TrianglePair{s, t});
  };
  BvhQueryBuffers buffers;
  bvh_traversal::visit_overlapping_pairs<self>(first, second, culled, buffers, num_threads, collect);
  std::vector<TrianglePair> pairs;
  for (const auto& list : found) pairs.insert(pairs.end(), list.begin(), list.end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace detail

// Pairs of triangles of one mesh whose boxes overlap, each once with a < b, sorted; with `culled`
// (one flag per node, SelfCulling::culled()), the pairs within a flagged node are left out.
inline std::vector<TrianglePair> self_pairs(const Bvh& bvh,
                                            SharedVertexPairs shared = SharedVertexPairs::skip,
                                            const std::vector<char>* culled = nullptr) {
  return detail::overlapping_pairs<true>(bvh, bvh, shared == SharedVertexPairs::keep,
                                         culled != nullptr ? culled->data() : nullptr);
}

// Pairs (triangle of `first`, triangle of `second`) whose boxes overlap, sorted.
inline std::vector<TrianglePair> pairs_between(const Bvh& first, const Bvh& second) {
  return detail::overlapping_pairs<false>(first, second, false, nullptr);
}

}  // namespace weft::testing
