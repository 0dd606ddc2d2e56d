#include "collision/candidates.hpp"

#include <algorithm>
#include <array>
#include <limits>

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

struct Box {
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

// The swept box of combined vertices `vertices`; an unbounded one when there are no boxes.
template <int N>
Box box_of(const SweptVertexBoxes* boxes, const std::array<int, N>& vertices) {
  Box box;
  if (!boxes) {
    box.lower = -box.lower;
    box.upper = -box.upper;
    return box;
  }
  for (const int v : vertices) {
    box.lower = box.lower.cwiseMin(boxes->lower.col(v));
    box.upper = box.upper.cwiseMax(boxes->upper.col(v));
  }
  return box;
}

bool within_gap(const Box& a, const Box& b, double gap) {
  return (a.lower.array() <= b.upper.array() + gap).all() && (b.lower.array() <= a.upper.array() + gap).all();
}

// Appends the candidates of triangle s of `first` against triangle t of `second`. With `self`
// the two are one mesh and corners or edge ends they share are skipped.
template <bool self>
void append_pair_candidates(int s, int t, const CandidateMesh& first, const CandidateMesh& second,
                            CollisionCandidates& candidates) {
  const Triangles& triangles_s = first.triangles;
  const Triangles& triangles_t = second.triangles;
  const SweptVertexBoxes* boxes = first.boxes;
  const double gap = boxes ? boxes->gap : 0.0;
  const int vs = first.offsets.vertex;
  const int vt = second.offsets.vertex;
  const Box box_s = box_of<3>(boxes, {vs + triangles_s(0, s), vs + triangles_s(1, s), vs + triangles_s(2, s)});
  const Box box_t = box_of<3>(boxes, {vt + triangles_t(0, t), vt + triangles_t(1, t), vt + triangles_t(2, t)});

  // Vertex-face: each corner of one triangle against the other triangle.
  for (int k = 0; k < 3; ++k) {
    const int v = triangles_s(k, s);
    if ((!self || !has_corner(triangles_t, t, v)) &&
        within_gap(box_of<1>(boxes, {vs + v}), box_t, gap)) {
      candidates.vertex_face.push_back({vs + v, second.offsets.triangle + t});
    }
    const int w = triangles_t(k, t);
    if ((!self || !has_corner(triangles_s, s, w)) &&
        within_gap(box_of<1>(boxes, {vt + w}), box_s, gap)) {
      candidates.vertex_face.push_back({vt + w, first.offsets.triangle + s});
    }
  }

  // Edge-edge: each side of one against each side of the other, unless they share an end.
  for (int i = 0; i < 3; ++i) {
    const int edge_s = first.topology.triangle_edges(i, s);
    const int a0 = first.topology.edges(0, edge_s), a1 = first.topology.edges(1, edge_s);
    const Box box_a = box_of<2>(boxes, {vs + a0, vs + a1});
    for (int j = 0; j < 3; ++j) {
      const int edge_t = second.topology.triangle_edges(j, t);
      const int b0 = second.topology.edges(0, edge_t), b1 = second.topology.edges(1, edge_t);
      if (self && (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1)) continue;
      if (!within_gap(box_a, box_of<2>(boxes, {vt + b0, vt + b1}), gap)) continue;
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

void append_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                            CollisionCandidates& candidates) {
  for (const TrianglePair& pair : pairs) append_pair_candidates<true>(pair.a, pair.b, mesh, mesh, candidates);
}

void append_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                               const CandidateMesh& second, CollisionCandidates& candidates) {
  for (const TrianglePair& pair : pairs) {
    append_pair_candidates<false>(pair.a, pair.b, first, second, candidates);
  }
}

void sort_candidates(CollisionCandidates& candidates) {
  sort_and_deduplicate(candidates.vertex_face);
  sort_and_deduplicate(candidates.edge_edge);
}

void add_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                         CollisionCandidates& candidates) {
  append_self_candidates(pairs, mesh, candidates);
  sort_candidates(candidates);
}

void add_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                            const CandidateMesh& second, CollisionCandidates& candidates) {
  append_candidates_between(pairs, first, second, candidates);
  sort_candidates(candidates);
}

}  // namespace weft
