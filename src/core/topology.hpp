#pragma once
// Edge and hinge connectivity of a triangle mesh, built once from the triangles.
#include <vector>

#include "core/math.hpp"

namespace weft {

struct MeshTopology {
  Eigen::Matrix2Xi edges;           // unique edges, smaller vertex index first, sorted (2 x n_edges)
  Eigen::Matrix2Xi edge_triangles;  // first two triangles at each edge; -1 where absent (2 x n_edges)
  Eigen::Matrix3Xi triangle_edges;  // edge of side k of each triangle, from vertex k to k+1 (3 x n_triangles)
  Eigen::Matrix4Xi hinges;          // interior edges: (v0, v1) the shared edge, v2 opposite in the
                                    // first triangle, v3 opposite in the second (4 x n_hinges);
                                    // (v0, v1, v2) is the first triangle counter-clockwise
  Eigen::VectorXi hinge_edges;      // edge index of each hinge (n_hinges)
  std::vector<int> boundary_edges;  // edges with exactly one triangle
  std::vector<int> non_manifold_edges;  // edges with three or more triangles (no hinge built)
  // Triangles around each vertex, in increasing index: those of vertex v are
  // vertex_triangles[vertex_triangle_start[v] .. vertex_triangle_start[v + 1]).
  std::vector<int> vertex_triangle_start;  // (n_vertices + 1)
  std::vector<int> vertex_triangles;       // (3 n_triangles)

  int num_edges() const { return static_cast<int>(edges.cols()); }
  int num_hinges() const { return static_cast<int>(hinges.cols()); }
};

// Whether triangles s and t (columns of `triangles`) have a corner in common.
inline bool share_vertex(const Triangles& triangles, int s, int t) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (triangles(i, s) == triangles(j, t)) return true;
    }
  }
  return false;
}

// The elements around each vertex (elements: K x n_elements vertex indices in [0, num_vertices)),
// in increasing element index: those of vertex v are list[starts[v] .. starts[v + 1]). Counted,
// then filled in element order (a counting sort).
template <int K>
void vertex_incidence(const Eigen::Matrix<int, K, Eigen::Dynamic>& elements, int num_vertices,
                      std::vector<int>& starts, std::vector<int>& list) {
  starts.assign(static_cast<std::size_t>(num_vertices) + 1, 0);
  for (Eigen::Index e = 0; e < elements.cols(); ++e) {
    for (int k = 0; k < K; ++k) ++starts[elements(k, e) + 1];
  }
  for (int v = 0; v < num_vertices; ++v) starts[v + 1] += starts[v];
  list.assign(static_cast<std::size_t>(K) * elements.cols(), 0);
  std::vector<int> fill(starts.begin(), starts.end() - 1);
  for (Eigen::Index e = 0; e < elements.cols(); ++e) {
    for (int k = 0; k < K; ++k) list[fill[elements(k, e)]++] = static_cast<int>(e);
  }
}

// Builds the topology; throws std::invalid_argument if an index is outside [0, num_vertices)
// or a triangle repeats a vertex.
MeshTopology build_topology(const Triangles& triangles, int num_vertices);

}  // namespace weft
