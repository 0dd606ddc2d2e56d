#include "collision/primitive_queries.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <limits>

#include "collision/bvh_traversal.hpp"
#include "collision/edge_edge.hpp"
#include "collision/point_triangle.hpp"

namespace weft {

namespace {

// ---- The filter a primitive pair passes to be written -------------------------------------

struct Box {
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

// The swept box of combined vertices `vertices`.
template <int N>
Box box_of(const SweptVertexBoxes& boxes, const std::array<int, N>& vertices) {
  Box box;
  for (const int v : vertices) {
    box.lower = box.lower.cwiseMin(boxes.lower.col(v));
    box.upper = box.upper.cwiseMax(boxes.upper.col(v));
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
bool separated_along(const SweptVertexBoxes& boxes, const std::array<int, NA>& a,
                     const std::array<int, NB>& b, const Vec3& axis) {
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

Vec3 box_center(const SweptVertexBoxes& boxes, int v) {
  return 0.5 * (boxes.lower.col(v) + boxes.upper.col(v));
}

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

bool edge_edge_separated(const SweptVertexBoxes& boxes, const std::array<int, 2>& a,
                         const std::array<int, 2>& b) {
  const Vec3 between = edge_edge_offset(box_center(boxes, a[0]), box_center(boxes, a[1]),
                                        box_center(boxes, b[0]), box_center(boxes, b[1]));
  const double distance = between.norm();
  if (!(distance > 0.0)) return false;
  return separated_along<2, 2>(boxes, a, b, between / distance);
}

// ---- Primitive pairs in combined indices ----------------------------------------------------

// Local vertex v of `vertices` against local triangle t of `faces` (the same mesh when `self`):
// written unless v is a corner of t, no triangle uses v, or the filter drops it.
template <bool self>
void add_vertex_face(const PrimitiveMesh& vertices, int v, const PrimitiveMesh& faces, int t,
                     const SweptVertexBoxes& boxes, std::vector<VertexFacePair>& out) {
  const MeshTopology& topology = vertices.topology;
  if (topology.vertex_triangle_start[v] == topology.vertex_triangle_start[v + 1]) return;
  const int vo = faces.offsets.vertex;
  const std::array<int, 3> corners{vo + faces.triangles(0, t), vo + faces.triangles(1, t),
                                   vo + faces.triangles(2, t)};
  const int vertex = vertices.offsets.vertex + v;
  if (self && (corners[0] == vertex || corners[1] == vertex || corners[2] == vertex)) return;
  if (!within_gap(box_of<1>(boxes, {vertex}), box_of<3>(boxes, corners), boxes.gap)) return;
  if (vertex_face_separated(boxes, vertex, corners)) return;
  out.push_back({vertex, faces.offsets.triangle + t});
}

// Local edge e of `first` against local edge f of `second` (the same mesh when `self`): written
// unless they share an end or the filter drops it. The filter is evaluated with the edge whose
// first triangle comes first in the combined order as primitive `a` (its closest-point
// direction is not exactly antisymmetric in floating point); the pair is written (min, max).
template <bool self>
void add_edge_edge(const PrimitiveMesh& first, int e, const PrimitiveMesh& second, int f,
                   const SweptVertexBoxes& boxes, std::vector<EdgeEdgePair>& out) {
  const int vo_a = first.offsets.vertex, vo_b = second.offsets.vertex;
  std::array<int, 2> a{vo_a + first.topology.edges(0, e), vo_a + first.topology.edges(1, e)};
  std::array<int, 2> b{vo_b + second.topology.edges(0, f), vo_b + second.topology.edges(1, f)};
  if (self && (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1])) return;
  if (!within_gap(box_of<2>(boxes, a), box_of<2>(boxes, b), boxes.gap)) return;
  const int triangle_a = first.offsets.triangle + first.topology.edge_triangles(0, e);
  const int triangle_b = second.offsets.triangle + second.topology.edge_triangles(0, f);
  if (triangle_a < triangle_b ? edge_edge_separated(boxes, a, b) : edge_edge_separated(boxes, b, a)) return;
  const int edge_a = first.offsets.edge + e, edge_b = second.offsets.edge + f;
  out.push_back({std::min(edge_a, edge_b), std::max(edge_a, edge_b)});
}

// ---- Full queries over the threads ----------------------------------------------------------

// Per-thread output lists, one a thread of this query, emptied.
void prepare_thread_lists(CollisionCandidates& candidates, int num_threads) {
  if (static_cast<int>(candidates.thread_vertex_faces.size()) < num_threads) {
    candidates.thread_vertex_faces.resize(num_threads);
    candidates.thread_edge_edges.resize(num_threads);
  }
  for (auto& list : candidates.thread_vertex_faces) list.clear();
  for (auto& list : candidates.thread_edge_edges) list.clear();
}

// The threads' lists appended in thread order. Which thread found a pair varies from run to run,
// so the order does too; sort_candidates() makes the lists the same on any number of threads.
void join_thread_lists(CollisionCandidates& candidates) {
  for (const auto& list : candidates.thread_vertex_faces) {
    candidates.vertex_face.insert(candidates.vertex_face.end(), list.begin(), list.end());
  }
  for (const auto& list : candidates.thread_edge_edges) {
    candidates.edge_edge.insert(candidates.edge_edge.end(), list.begin(), list.end());
  }
}

int query_threads() { return std::max(1, omp_get_max_threads()); }

// Vertices of `vertices` against the triangles of `faces`.
template <bool self>
void query_vertex_faces(const PrimitiveMesh& vertices, const PrimitiveMesh& faces,
                        const SweptVertexBoxes& boxes, BvhQueryBuffers& buffers,
                        CollisionCandidates& candidates) {
  auto visit = [&](int thread, int v, int t) {
    add_vertex_face<self>(vertices, v, faces, t, boxes, candidates.thread_vertex_faces[thread]);
  };
  bvh_traversal::visit_overlapping_pairs<false>(vertices.vertex_bvh, faces.triangle_bvh, nullptr, buffers,
                                                query_threads(), visit);
}

}  // namespace

Triangles point_entries(int vertex_offset, int num_vertices) {
  Triangles entries(3, num_vertices);
  for (int v = 0; v < num_vertices; ++v) entries.col(v).setConstant(vertex_offset + v);
  return entries;
}

Triangles segment_entries(const Eigen::Matrix2Xi& edges, int vertex_offset) {
  Triangles entries(3, edges.cols());
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    entries.col(e) << vertex_offset + edges(0, e), vertex_offset + edges(1, e), vertex_offset + edges(1, e);
  }
  return entries;
}

void append_self_primitive_candidates(const PrimitiveMesh& mesh, const SweptVertexBoxes& boxes,
                                      BvhQueryBuffers& buffers, CollisionCandidates& candidates) {
  prepare_thread_lists(candidates, query_threads());
  query_vertex_faces<true>(mesh, mesh, boxes, buffers, candidates);
  // Edge pairs within the hierarchy, each once; the order of (e, f) is the leaf order.
  auto visit = [&](int thread, int e, int f) {
    add_edge_edge<true>(mesh, e, mesh, f, boxes, candidates.thread_edge_edges[thread]);
  };
  bvh_traversal::visit_overlapping_pairs<true>(mesh.edge_bvh, mesh.edge_bvh, nullptr, buffers,
                                               query_threads(), visit);
  join_thread_lists(candidates);
}

void append_primitive_candidates_between(const PrimitiveMesh& first, const PrimitiveMesh& second,
                                         const SweptVertexBoxes& boxes, BvhQueryBuffers& buffers,
                                         CollisionCandidates& candidates) {
  prepare_thread_lists(candidates, query_threads());
  query_vertex_faces<false>(first, second, boxes, buffers, candidates);
  query_vertex_faces<false>(second, first, boxes, buffers, candidates);
  auto visit = [&](int thread, int e, int f) {
    add_edge_edge<false>(first, e, second, f, boxes, candidates.thread_edge_edges[thread]);
  };
  bvh_traversal::visit_overlapping_pairs<false>(first.edge_bvh, second.edge_bvh, nullptr, buffers,
                                                query_threads(), visit);
  join_thread_lists(candidates);
}

OwnedPrimitives owned_primitives(const MeshTopology& topology, int num_triangles) {
  OwnedPrimitives owned;
  const int num_vertices = static_cast<int>(topology.vertex_triangle_start.size()) - 1;
  std::vector<int> vertex_owner(num_vertices, -1);
  for (int v = 0; v < num_vertices; ++v) {
    if (topology.vertex_triangle_start[v] < topology.vertex_triangle_start[v + 1]) {
      vertex_owner[v] = topology.vertex_triangles[topology.vertex_triangle_start[v]];
    }
  }
  // Counting sorts by owner, so each triangle's list is ascending.
  const auto sort_by_owner = [&](const auto& owner_of, int count, std::vector<int>& start,
                                 std::vector<int>& list) {
    start.assign(num_triangles + 1, 0);
    for (int i = 0; i < count; ++i) {
      if (owner_of(i) >= 0) ++start[owner_of(i) + 1];
    }
    for (int t = 0; t < num_triangles; ++t) start[t + 1] += start[t];
    list.resize(start[num_triangles]);
    std::vector<int> next(start.begin(), start.end() - 1);
    for (int i = 0; i < count; ++i) {
      if (owner_of(i) >= 0) list[next[owner_of(i)]++] = i;
    }
  };
  sort_by_owner([&](int v) { return vertex_owner[v]; }, num_vertices, owned.vertex_start, owned.vertices);
  sort_by_owner([&](int e) { return topology.edge_triangles(0, e); }, topology.num_edges(), owned.edge_start,
                owned.edges);
  return owned;
}

void append_self_candidates_culled(const PrimitiveMesh& mesh, const OwnedPrimitives& owned,
                                   const SweptVertexBoxes& boxes, const std::vector<char>& culled,
                                   const std::vector<int>* within, BvhQueryBuffers& buffers,
                                   CollisionCandidates& candidates) {
  prepare_thread_lists(candidates, query_threads());
  // Triangles s and t, boxes overlapping: s's vertices against t and t's against s, s's edges
  // against t's. A vertex's box lies in its owner's, so a pair of boxes within the gap lies in a
  // pair of triangle boxes that overlap: the walk meets every pair the primitive queries meet.
  auto visit = [&](int thread, int s, int t) {
    std::vector<VertexFacePair>& vertex_faces = candidates.thread_vertex_faces[thread];
    for (int k = owned.vertex_start[s]; k < owned.vertex_start[s + 1]; ++k) {
      add_vertex_face<true>(mesh, owned.vertices[k], mesh, t, boxes, vertex_faces);
    }
    for (int k = owned.vertex_start[t]; k < owned.vertex_start[t + 1]; ++k) {
      add_vertex_face<true>(mesh, owned.vertices[k], mesh, s, boxes, vertex_faces);
    }
    for (int i = owned.edge_start[s]; i < owned.edge_start[s + 1]; ++i) {
      for (int j = owned.edge_start[t]; j < owned.edge_start[t + 1]; ++j) {
        add_edge_edge<true>(mesh, owned.edges[i], mesh, owned.edges[j], boxes,
                            candidates.thread_edge_edges[thread]);
      }
    }
  };
  bvh_traversal::visit_overlapping_pairs<true>(mesh.triangle_bvh, mesh.triangle_bvh,
                                               culled.empty() ? nullptr : culled.data(), buffers,
                                               query_threads(), visit, within);
  join_thread_lists(candidates);
}

void list_moved_primitives(const PrimitiveMesh& mesh, const std::vector<char>& moved,
                           MovedPrimitives& listed) {
  listed.vertices.clear();
  listed.triangles.clear();
  listed.edges.clear();
  const int vo = mesh.offsets.vertex;
  const int num_vertices = static_cast<int>(mesh.topology.vertex_triangle_start.size()) - 1;
  for (int v = 0; v < num_vertices; ++v) {
    if (moved[vo + v]) listed.vertices.push_back(v);
  }
  if (listed.vertices.empty()) return;
  for (int t = 0; t < mesh.triangles.cols(); ++t) {
    if (moved[vo + mesh.triangles(0, t)] || moved[vo + mesh.triangles(1, t)] ||
        moved[vo + mesh.triangles(2, t)]) {
      listed.triangles.push_back(t);
    }
  }
  for (int e = 0; e < mesh.topology.num_edges(); ++e) {
    if (moved[vo + mesh.topology.edges(0, e)] || moved[vo + mesh.topology.edges(1, e)])
      listed.edges.push_back(e);
  }
}

void append_moved_primitive_candidates(const PrimitiveMesh& mesh, const MovedPrimitives& listed,
                                       const PrimitiveMesh& other, bool self, const SweptVertexBoxes& boxes,
                                       std::vector<std::vector<int>>& thread_scratch,
                                       CollisionCandidates& candidates) {
  if (listed.empty()) return;
  const int threads = query_threads();
  prepare_thread_lists(candidates, threads);
  if (static_cast<int>(thread_scratch.size()) < threads) thread_scratch.resize(threads);
  const int num_vertices = static_cast<int>(listed.vertices.size());
  const int num_triangles = static_cast<int>(listed.triangles.size());
  const int total = num_vertices + num_triangles + static_cast<int>(listed.edges.size());
  // Each listed primitive's box against the other mesh's hierarchy, the primitives shared among
  // the threads. A pair met from both its primitives (both listed) is written twice; the caller's
  // sort_candidates() keeps it once.
  const auto add_vertex_face_pair = [&](const PrimitiveMesh& vertices, int v, const PrimitiveMesh& faces,
                                        int t, std::vector<VertexFacePair>& out) {
    if (self) {
      add_vertex_face<true>(vertices, v, faces, t, boxes, out);
    } else {
      add_vertex_face<false>(vertices, v, faces, t, boxes, out);
    }
  };
#pragma omp parallel for schedule(dynamic, 8) num_threads(threads) if (total > 64)
  for (int k = 0; k < total; ++k) {
    const int thread = omp_get_thread_num();
    std::vector<int>& found = thread_scratch[thread];
    std::vector<VertexFacePair>& vertex_faces = candidates.thread_vertex_faces[thread];
    if (k < num_vertices) {  // a moved vertex against the other mesh's triangles
      const int v = listed.vertices[k];
      find_triangles_in_box(other.triangle_bvh, mesh.vertex_bvh.triangle_boxes()[v], found);
      for (const int t : found) add_vertex_face_pair(mesh, v, other, t, vertex_faces);
    } else if (k < num_vertices + num_triangles) {  // a triangle with a moved corner against its vertices
      const int t = listed.triangles[k - num_vertices];
      find_triangles_in_box(other.vertex_bvh, mesh.triangle_bvh.triangle_boxes()[t], found);
      for (const int v : found) add_vertex_face_pair(other, v, mesh, t, vertex_faces);
    } else {  // an edge with a moved end against its edges (add_edge_edge skips shared ends)
      const int e = listed.edges[k - num_vertices - num_triangles];
      find_triangles_in_box(other.edge_bvh, mesh.edge_bvh.triangle_boxes()[e], found);
      for (const int f : found) {
        if (self) {
          add_edge_edge<true>(mesh, e, other, f, boxes, candidates.thread_edge_edges[thread]);
        } else {
          add_edge_edge<false>(mesh, e, other, f, boxes, candidates.thread_edge_edges[thread]);
        }
      }
    }
  }
  join_thread_lists(candidates);
}

}  // namespace weft
