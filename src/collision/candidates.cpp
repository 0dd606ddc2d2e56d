#include "collision/candidates.hpp"

#include <algorithm>

namespace weft {

namespace {

bool has_corner(const Triangles& triangles, int t, int v) {
  return triangles(0, t) == v || triangles(1, t) == v || triangles(2, t) == v;
}

template <typename T>
void sort_and_deduplicate(std::vector<T>& items) {
  std::sort(items.begin(), items.end());
  items.erase(std::unique(items.begin(), items.end()), items.end());
}

// Appends the candidates of triangle s of `first` against triangle t of `second`. With `self`
// the two are one mesh and corners or edge ends they share are skipped.
template <bool self>
void append_pair_candidates(int s, int t, const CandidateMesh& first, const CandidateMesh& second,
                            CollisionCandidates& candidates) {
  const Triangles& triangles_s = first.triangles;
  const Triangles& triangles_t = second.triangles;

  // Vertex-face: each corner of one triangle against the other triangle.
  for (int k = 0; k < 3; ++k) {
    const int v = triangles_s(k, s);
    if (!self || !has_corner(triangles_t, t, v)) {
      candidates.vertex_face.push_back({first.offsets.vertex + v, second.offsets.triangle + t});
    }
    const int w = triangles_t(k, t);
    if (!self || !has_corner(triangles_s, s, w)) {
      candidates.vertex_face.push_back({second.offsets.vertex + w, first.offsets.triangle + s});
    }
  }

  // Edge-edge: each side of one against each side of the other, unless they share an end.
  for (int i = 0; i < 3; ++i) {
    const int edge_s = first.topology.triangle_edges(i, s);
    for (int j = 0; j < 3; ++j) {
      const int edge_t = second.topology.triangle_edges(j, t);
      if (self) {
        const int a0 = first.topology.edges(0, edge_s), a1 = first.topology.edges(1, edge_s);
        const int b0 = second.topology.edges(0, edge_t), b1 = second.topology.edges(1, edge_t);
        if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) continue;
      }
      const int a = first.offsets.edge + edge_s;
      const int b = second.offsets.edge + edge_t;
      candidates.edge_edge.push_back({std::min(a, b), std::max(a, b)});
    }
  }
}

}  // namespace

MeshIndexOffsets next_offsets(const MeshIndexOffsets& offsets, int num_vertices, int num_triangles,
                              int num_edges) {
  return {offsets.vertex + num_vertices, offsets.triangle + num_triangles, offsets.edge + num_edges};
}

void add_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                         CollisionCandidates& candidates) {
  for (const TrianglePair& pair : pairs) append_pair_candidates<true>(pair.a, pair.b, mesh, mesh, candidates);
  sort_and_deduplicate(candidates.vertex_face);
  sort_and_deduplicate(candidates.edge_edge);
}

void add_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                            const CandidateMesh& second, CollisionCandidates& candidates) {
  for (const TrianglePair& pair : pairs)
    append_pair_candidates<false>(pair.a, pair.b, first, second, candidates);
  sort_and_deduplicate(candidates.vertex_face);
  sort_and_deduplicate(candidates.edge_edge);
}

}  // namespace weft
