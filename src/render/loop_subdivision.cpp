#include "render/loop_subdivision.hpp"

#include <vector>

#include "core/topology.hpp"

namespace weft {

namespace {

using Sparse = Eigen::SparseMatrix<double>;

// One round: the fine triangles and the (n_fine x n_coarse) weights.
void subdivide_once(const Triangles& triangles, int num_vertices, Triangles& fine_triangles, Sparse& weights) {
  const MeshTopology topology = build_topology(triangles, num_vertices);
  const int num_edges = topology.num_edges();
  std::vector<bool> boundary_edge(static_cast<size_t>(num_edges), false);
  for (int e : topology.boundary_edges) boundary_edge[static_cast<size_t>(e)] = true;
  for (int e : topology.non_manifold_edges) boundary_edge[static_cast<size_t>(e)] = true;

  // Neighbours of each vertex, all and along the boundary; triangles touching each vertex.
  std::vector<std::vector<int>> neighbours(static_cast<size_t>(num_vertices));
  std::vector<std::vector<int>> boundary_neighbours(static_cast<size_t>(num_vertices));
  std::vector<int> triangle_count(static_cast<size_t>(num_vertices), 0);
  for (int e = 0; e < num_edges; ++e) {
    const int a = topology.edges(0, e), b = topology.edges(1, e);
    neighbours[static_cast<size_t>(a)].push_back(b);
    neighbours[static_cast<size_t>(b)].push_back(a);
    if (boundary_edge[static_cast<size_t>(e)]) {
      boundary_neighbours[static_cast<size_t>(a)].push_back(b);
      boundary_neighbours[static_cast<size_t>(b)].push_back(a);
    }
  }
  for (int t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) ++triangle_count[static_cast<size_t>(triangles(k, t))];
  }

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(8 * num_vertices + 4 * num_edges));
  // Even vertices: the old ones, smoothed.
  for (int v = 0; v < num_vertices; ++v) {
    const auto& ring = neighbours[static_cast<size_t>(v)];
    const auto& rim = boundary_neighbours[static_cast<size_t>(v)];
    if (rim.empty() && ring.size() >= 3) {
      const double n = static_cast<double>(ring.size());
      const double beta = ring.size() == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
      entries.emplace_back(v, v, 1.0 - n * beta);
      for (int u : ring) entries.emplace_back(v, u, beta);
    } else if (rim.size() == 2 && triangle_count[static_cast<size_t>(v)] > 1) {
      entries.emplace_back(v, v, 0.75);
      for (int u : rim) entries.emplace_back(v, u, 0.125);
    } else {
      entries.emplace_back(v, v, 1.0);  // corner, isolated or non-manifold vertex: kept
    }
  }
  // Odd vertices: one per edge.
  for (int e = 0; e < num_edges; ++e) {
    const int row = num_vertices + e;
    const int a = topology.edges(0, e), b = topology.edges(1, e);
    const int t0 = topology.edge_triangles(0, e), t1 = topology.edge_triangles(1, e);
    if (boundary_edge[static_cast<size_t>(e)] || t0 < 0 || t1 < 0) {
      entries.emplace_back(row, a, 0.5);
      entries.emplace_back(row, b, 0.5);
      continue;
    }
    entries.emplace_back(row, a, 0.375);
    entries.emplace_back(row, b, 0.375);
    for (int t : {t0, t1}) {
      for (int k = 0; k < 3; ++k) {
        const int c = triangles(k, t);
        if (c != a && c != b) entries.emplace_back(row, c, 0.125);
      }
    }
  }
  weights.resize(num_vertices + num_edges, num_vertices);
  weights.setFromTriplets(entries.begin(), entries.end());

  // Each triangle becomes three corner triangles and the middle one, orientation kept.
  fine_triangles.resize(3, 4 * triangles.cols());
  for (int t = 0; t < triangles.cols(); ++t) {
    const int a = triangles(0, t), b = triangles(1, t), c = triangles(2, t);
    const int ab = num_vertices + topology.triangle_edges(0, t);
    const int bc = num_vertices + topology.triangle_edges(1, t);
    const int ca = num_vertices + topology.triangle_edges(2, t);
    fine_triangles.col(4 * t + 0) << a, ab, ca;
    fine_triangles.col(4 * t + 1) << b, bc, ab;
    fine_triangles.col(4 * t + 2) << c, ca, bc;
    fine_triangles.col(4 * t + 3) << ab, bc, ca;
  }
}

}  // namespace

LoopSubdivision make_loop_subdivision(const Triangles& triangles, int num_vertices, int levels) {
  LoopSubdivision result;
  result.levels = std::max(levels, 0);
  result.triangles = triangles;
  result.coarse_to_fine.resize(num_vertices, num_vertices);
  result.coarse_to_fine.setIdentity();
  int current_vertices = num_vertices;
  for (int level = 0; level < result.levels; ++level) {
    Triangles fine;
    Sparse step;
    subdivide_once(result.triangles, current_vertices, fine, step);
    result.coarse_to_fine = (step * result.coarse_to_fine).pruned();
    result.triangles = std::move(fine);
    current_vertices = static_cast<int>(step.rows());
  }
  return result;
}

}  // namespace weft
