#include "collision/candidates.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"
#include "core/parallel_chunks.hpp"

namespace weft {

namespace {

bool has_corner(const Triangles& triangles, int t, int v) {
  return triangles(0, t) == v || triangles(1, t) == v || triangles(2, t) == v;
}

// Sorts 64-bit keys and drops repeats: least-significant-digit radix sort, a byte a pass, passes
// whose byte is the same in every key skipped (indices below 2^16 leave half the passes out).
// Several times faster than std::sort on the tens of thousands of pairs of a step.
void sort_unique_keys(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch) {
  const size_t n = keys.size();
  scratch.resize(n);
  for (int shift = 0; shift < 64; shift += 8) {
    std::array<size_t, 257> start{};
    for (const std::uint64_t key : keys) ++start[((key >> shift) & 255u) + 1];
    if (std::find(start.begin() + 1, start.end(), n) != start.end()) continue;  // one digit for all
    for (int d = 0; d < 256; ++d) start[d + 1] += start[d];
    for (const std::uint64_t key : keys) scratch[start[(key >> shift) & 255u]++] = key;
    keys.swap(scratch);
  }
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

// Sorts pairs of non-negative indices by (first, second) and removes duplicates, through keys
// first << 32 | second.
template <typename T, int T::*First, int T::*Second>
void sort_and_deduplicate(std::vector<T>& items, std::vector<std::uint64_t>& keys,
                          std::vector<std::uint64_t>& scratch) {
  keys.resize(items.size());
  for (size_t k = 0; k < items.size(); ++k) {
    keys[k] = std::uint64_t(std::uint32_t(items[k].*First)) << 32 | std::uint32_t(items[k].*Second);
  }
  sort_unique_keys(keys, scratch);
  items.resize(keys.size());
  for (size_t k = 0; k < keys.size(); ++k) {
    items[k].*First = static_cast<int>(keys[k] >> 32);
    items[k].*Second = static_cast<int>(keys[k] & 0xffffffffu);
  }
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

// Whether the vertex boxes of primitive `a` and those of primitive `b` are more than the gap apart
// along `axis` (unit, pointing from a towards b), scaled by |axis|_1. Every point of a primitive,
// at any time of a motion within its corners' boxes, projects inside the projections of those
// boxes. The scale keeps the guarantee of the coordinate-axis test (within_gap) that
// CollisionPhase::verify_motion relies on: a vertex that stays within s of its box per
// coordinate moves at most s |axis|_1 along the axis.
template <int NA, int NB>
bool separated_along(const SweptVertexBoxes& boxes, const std::array<int, NA>& a, const std::array<int, NB>& b,
                     const Vec3& axis) {
  const Vec3 abs_axis = axis.cwiseAbs();
  double a_high = -std::numeric_limits<double>::infinity();
  for (const int v : a) {  // 2 (n . c + |n| . half) = n . (l + u) + |n| . (u - l)
    a_high = std::max(a_high, axis.dot(boxes.lower.col(v) + boxes.upper.col(v)) +
                                  abs_axis.dot(boxes.upper.col(v) - boxes.lower.col(v)));
  }
  double b_low = std::numeric_limits<double>::infinity();
  for (const int v : b) {
    b_low = std::min(b_low, axis.dot(boxes.lower.col(v) + boxes.upper.col(v)) -
                                abs_axis.dot(boxes.upper.col(v) - boxes.lower.col(v)));
  }
  return 0.5 * (b_low - a_high) > abs_axis.sum() * boxes.gap;
}

Vec3 box_center(const SweptVertexBoxes& boxes, int v) { return 0.5 * (boxes.lower.col(v) + boxes.upper.col(v)); }

// The second filter of a pair whose boxes pass within_gap: the separating test along the
// direction between the primitives' closest points at their boxes' centres. It drops the pairs a
// coordinate-axis test cannot, above all in a flat grid, where the corner a right triangle lacks
// lies in the triangle's box and the edges of the cell next door touch its diagonal's box.
bool vertex_face_separated(const SweptVertexBoxes& boxes, int v, const std::array<int, 3>& corners) {
  const Vec3 p = box_center(boxes, v);
  const PointTriangleClosest closest = point_triangle_closest(
      p, box_center(boxes, corners[0]), box_center(boxes, corners[1]), box_center(boxes, corners[2]));
  if (!(closest.distance > 0.0)) return false;
  return separated_along<3, 1>(boxes, corners, {v}, (p - closest.closest) / closest.distance);
}

bool edge_edge_separated(const SweptVertexBoxes& boxes, const std::array<int, 2>& a, const std::array<int, 2>& b) {
  const Vec3 between = edge_edge_offset(box_center(boxes, a[0]), box_center(boxes, a[1]), box_center(boxes, b[0]),
                                        box_center(boxes, b[1]));
  const double distance = between.norm();
  if (!(distance > 0.0)) return false;
  return separated_along<2, 2>(boxes, a, b, between / distance);
}

// Whether triangle s, one of those around vertex v, is v's designated triangle against any
// triangle t (TrianglePairList::complete): the first around v. Within one mesh t is not around v
// (v is not its corner), so the pair (s, t) is two different triangles that a query keeping
// shared-vertex pairs reports.
bool designates_vertex(const CandidateMesh& mesh, int v, int s) {
  return mesh.topology.vertex_triangles[mesh.topology.vertex_triangle_start[v]] == s;
}

// Whether (s, t) is the designated pair of edge e (a side of s) against edge f (a side of t):
// their first triangles. Within one mesh e and f share no end, so no triangle is at both.
bool designates_edges(const CandidateMesh& first, const CandidateMesh& second, int e, int f, int s, int t) {
  return first.topology.edge_triangles(0, e) == s && second.topology.edge_triangles(0, f) == t;
}

// Appends the candidates of triangle s of `first` against triangle t of `second`. With `self`
// the two are one mesh and corners or edge ends they share are skipped. With `designated` only
// the primitive pairs whose designated triangle pair is (s, t) are written.
template <bool self>
void append_pair_candidates(int s, int t, const CandidateMesh& first, const CandidateMesh& second, bool designated,
                            std::vector<VertexFacePair>& vertex_faces, std::vector<EdgeEdgePair>& edge_edges) {
  const Triangles& triangles_s = first.triangles;
  const Triangles& triangles_t = second.triangles;
  const SweptVertexBoxes* boxes = first.boxes;
  const double gap = boxes ? boxes->gap : 0.0;
  const int vs = first.offsets.vertex;
  const int vt = second.offsets.vertex;

  const std::array<int, 3> corners_s{vs + triangles_s(0, s), vs + triangles_s(1, s), vs + triangles_s(2, s)};
  const std::array<int, 3> corners_t{vt + triangles_t(0, t), vt + triangles_t(1, t), vt + triangles_t(2, t)};
  // The triangles' boxes, computed when a designated vertex needs them (most pairs of a
  // complete list designate none).
  Box box_s, box_t;
  bool have_box_s = false, have_box_t = false;
  const auto triangle_box = [&](bool of_s) -> const Box& {
    bool& have = of_s ? have_box_s : have_box_t;
    Box& box = of_s ? box_s : box_t;
    if (!have) box = box_of<3>(boxes, of_s ? corners_s : corners_t);
    have = true;
    return box;
  };

  // Vertex-face: each corner of one triangle against the other triangle.
  for (int k = 0; k < 3; ++k) {
    const int v = triangles_s(k, s);
    if ((!self || !has_corner(triangles_t, t, v)) && (!designated || designates_vertex(first, v, s)) &&
        within_gap(box_of<1>(boxes, {vs + v}), triangle_box(false), gap) &&
        !(boxes && vertex_face_separated(*boxes, vs + v, corners_t))) {
      vertex_faces.push_back({vs + v, second.offsets.triangle + t});
    }
    const int w = triangles_t(k, t);
    if ((!self || !has_corner(triangles_s, s, w)) && (!designated || designates_vertex(second, w, t)) &&
        within_gap(box_of<1>(boxes, {vt + w}), triangle_box(true), gap) &&
        !(boxes && vertex_face_separated(*boxes, vt + w, corners_s))) {
      vertex_faces.push_back({vt + w, first.offsets.triangle + s});
    }
  }

  // Edge-edge: each side of one against each side of the other, unless they share an end.
  for (int i = 0; i < 3; ++i) {
    const int edge_s = first.topology.triangle_edges(i, s);
    if (designated && first.topology.edge_triangles(0, edge_s) != s) continue;
    const int a0 = first.topology.edges(0, edge_s), a1 = first.topology.edges(1, edge_s);
    const Box box_a = box_of<2>(boxes, {vs + a0, vs + a1});
    for (int j = 0; j < 3; ++j) {
      const int edge_t = second.topology.triangle_edges(j, t);
      const int b0 = second.topology.edges(0, edge_t), b1 = second.topology.edges(1, edge_t);
      if (self && (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1)) continue;
      if (designated && !designates_edges(first, second, edge_s, edge_t, s, t)) continue;
      if (!within_gap(box_a, box_of<2>(boxes, {vt + b0, vt + b1}), gap)) continue;
      if (boxes && edge_edge_separated(*boxes, {vs + a0, vs + a1}, {vt + b0, vt + b1})) continue;
      const int a = first.offsets.edge + edge_s;
      const int b = second.offsets.edge + edge_t;
      edge_edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
}

// The candidates of every pair, appended in pair order. Large lists are cut into one contiguous
// chunk a thread, each written to its own buffer, and the buffers appended in chunk order: the
// same lists on any number of threads.
template <bool self>
void append_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                       const CandidateMesh& second, TrianglePairList list, CollisionCandidates& candidates) {
  const bool designated = list == TrianglePairList::complete && first.boxes &&
                          (!self || first.topology.non_manifold_edges.empty());
  constexpr int pairs_per_thread = 1024;
  const int num_pairs = static_cast<int>(pairs.size());
  const int threads = std::min(std::max(1, omp_get_max_threads()), std::max(1, num_pairs / pairs_per_thread));
  if (threads == 1) {
    for (const TrianglePair& pair : pairs) {
      append_pair_candidates<self>(pair.a, pair.b, first, second, designated, candidates.vertex_face,
                                   candidates.edge_edge);
    }
    return;
  }
  auto& thread_vertex_faces = candidates.thread_vertex_faces;
  auto& thread_edge_edges = candidates.thread_edge_edges;
  if (static_cast<int>(thread_vertex_faces.size()) < threads) {
    thread_vertex_faces.resize(threads);
    thread_edge_edges.resize(threads);
  }
  for (int k = 0; k < threads; ++k) {
    thread_vertex_faces[k].clear();
    thread_edge_edges[k].clear();
  }
#pragma omp parallel num_threads(threads)
  {
    const int count = omp_get_num_threads();
    for (int k = omp_get_thread_num(); k < threads; k += count) {
      const int end = chunk_begin(k + 1, num_pairs, threads);
      for (int i = chunk_begin(k, num_pairs, threads); i < end; ++i) {
        append_pair_candidates<self>(pairs[i].a, pairs[i].b, first, second, designated, thread_vertex_faces[k],
                                     thread_edge_edges[k]);
      }
    }
  }
  for (int k = 0; k < threads; ++k) {
    candidates.vertex_face.insert(candidates.vertex_face.end(), thread_vertex_faces[k].begin(),
                                  thread_vertex_faces[k].end());
    candidates.edge_edge.insert(candidates.edge_edge.end(), thread_edge_edges[k].begin(), thread_edge_edges[k].end());
  }
}

}  // namespace

MeshIndexOffsets next_offsets(const MeshIndexOffsets& offsets, int num_vertices, int num_triangles,
                              int num_edges) {
  return {offsets.vertex + num_vertices, offsets.triangle + num_triangles, offsets.edge + num_edges};
}

void append_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                            CollisionCandidates& candidates, TrianglePairList list) {
  append_candidates<true>(pairs, mesh, mesh, list, candidates);
}

void append_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                               const CandidateMesh& second, CollisionCandidates& candidates, TrianglePairList list) {
  append_candidates<false>(pairs, first, second, list, candidates);
}

void sort_candidates(CollisionCandidates& candidates) {
  sort_and_deduplicate<VertexFacePair, &VertexFacePair::vertex, &VertexFacePair::triangle>(
      candidates.vertex_face, candidates.sort_keys, candidates.sort_scratch);
  sort_and_deduplicate<EdgeEdgePair, &EdgeEdgePair::edge_a, &EdgeEdgePair::edge_b>(
      candidates.edge_edge, candidates.sort_keys, candidates.sort_scratch);
}

namespace {

template <typename T>
void merge_new(std::vector<T>& all, std::vector<T>& added, std::vector<T>& scratch) {
  // Set difference in place (both sorted), then the two sorted runs merged through `scratch`.
  auto in_all = all.begin();
  auto kept = added.begin();
  for (auto it = added.begin(); it != added.end(); ++it) {
    in_all = std::lower_bound(in_all, all.end(), *it);
    if (in_all == all.end() || !(*in_all == *it)) *kept++ = *it;
  }
  added.erase(kept, added.end());
  if (added.empty()) return;
  scratch.resize(all.size() + added.size());
  std::merge(all.begin(), all.end(), added.begin(), added.end(), scratch.begin());
  all.swap(scratch);
}

}  // namespace

void merge_new_candidates(CollisionCandidates& all, CollisionCandidates& added) {
  merge_new(all.vertex_face, added.vertex_face, all.vertex_face_scratch);
  merge_new(all.edge_edge, added.edge_edge, all.edge_edge_scratch);
}

void add_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                         CollisionCandidates& candidates, TrianglePairList list) {
  append_self_candidates(pairs, mesh, candidates, list);
  sort_candidates(candidates);
}

void add_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                            const CandidateMesh& second, CollisionCandidates& candidates,
                            TrianglePairList list) {
  append_candidates_between(pairs, first, second, candidates, list);
  sort_candidates(candidates);
}

}  // namespace weft
