#include "core/topology.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace weft {

namespace {

// One side of one triangle: its edge as a sortable key (smaller vertex in the high bits) and
// where it sits, 3 * triangle + side.
struct TriangleSide {
  std::uint64_t edge_key;
  int slot;

  bool operator<(const TriangleSide& other) const {
    return edge_key != other.edge_key ? edge_key < other.edge_key : slot < other.slot;
  }
};

std::uint64_t edge_key(int a, int b) {
  const auto low = static_cast<std::uint64_t>(std::min(a, b));
  const auto high = static_cast<std::uint64_t>(std::max(a, b));
  return (low << 32) | high;
}

void check_triangles(const Triangles& triangles, int num_vertices) {
  if (num_vertices < 0) {
    throw std::invalid_argument("build_topology: negative vertex count " + std::to_string(num_vertices));
  }
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int v = triangles(k, t);
      if (v < 0 || v >= num_vertices) {
        throw std::invalid_argument("build_topology: triangle " + std::to_string(t) + " has vertex index " +
                                    std::to_string(v) + " outside [0, " + std::to_string(num_vertices) + ")");
      }
    }
    if (triangles(0, t) == triangles(1, t) || triangles(1, t) == triangles(2, t) ||
        triangles(2, t) == triangles(0, t)) {
      throw std::invalid_argument("build_topology: triangle " + std::to_string(t) + " repeats a vertex (" +
                                  std::to_string(triangles(0, t)) + ", " + std::to_string(triangles(1, t)) +
                                  ", " + std::to_string(triangles(2, t)) + ")");
    }
  }
}

}  // namespace

MeshTopology build_topology(const Triangles& triangles, int num_vertices) {
  check_triangles(triangles, num_vertices);
  const int num_triangles = static_cast<int>(triangles.cols());

  // Sorting the sides by edge key brings the sides of each edge together, in triangle order, so
  // edges come out unique and sorted in O(n log n).
  std::vector<TriangleSide> sides(3 * static_cast<std::size_t>(num_triangles));
  for (int t = 0; t < num_triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      sides[3 * t + k] = {edge_key(triangles(k, t), triangles((k + 1) % 3, t)), 3 * t + k};
    }
  }
  std::sort(sides.begin(), sides.end());

  // Runs of equal keys: [run_starts[e], run_starts[e + 1]) are the sides of edge e.
  std::vector<int> run_starts;
  run_starts.reserve(sides.size() / 2 + 2);
  for (std::size_t s = 0; s < sides.size(); ++s) {
    if (s == 0 || sides[s].edge_key != sides[s - 1].edge_key) run_starts.push_back(static_cast<int>(s));
  }
  const int num_edges = static_cast<int>(run_starts.size());
  run_starts.push_back(static_cast<int>(sides.size()));

  MeshTopology topology;
  topology.edges.resize(2, num_edges);
  topology.edge_triangles.setConstant(2, num_edges, -1);
  topology.triangle_edges.resize(3, num_triangles);
  std::vector<int> hinge_edges;
  for (int e = 0; e < num_edges; ++e) {
    const int begin = run_starts[e];
    const int end = run_starts[e + 1];
    topology.edges(0, e) = static_cast<int>(sides[begin].edge_key >> 32);
    topology.edges(1, e) = static_cast<int>(sides[begin].edge_key & 0xffffffffu);
    for (int s = begin; s < end; ++s) {
      if (s - begin < 2) topology.edge_triangles(s - begin, e) = sides[s].slot / 3;
      topology.triangle_edges(sides[s].slot % 3, sides[s].slot / 3) = e;
    }
    const int count = end - begin;
    if (count == 1) {
      topology.boundary_edges.push_back(e);
    } else if (count == 2) {
      hinge_edges.push_back(e);
    } else {
      topology.non_manifold_edges.push_back(e);
    }
  }

  // Hinges: (v0, v1) in the first triangle's winding, so (v0, v1, v2) is that triangle
  // counter-clockwise; v3 is the vertex of the second triangle opposite the edge.
  const int num_hinges = static_cast<int>(hinge_edges.size());
  topology.hinges.resize(4, num_hinges);
  topology.hinge_edges.resize(num_hinges);
  for (int h = 0; h < num_hinges; ++h) {
    const int e = hinge_edges[h];
    const int first = sides[run_starts[e]].slot;
    const int second = sides[run_starts[e] + 1].slot;
    const int t0 = first / 3, k0 = first % 3;
    const int t1 = second / 3, k1 = second % 3;
    topology.hinges.col(h) << triangles(k0, t0), triangles((k0 + 1) % 3, t0), triangles((k0 + 2) % 3, t0),
        triangles((k1 + 2) % 3, t1);
    topology.hinge_edges[h] = e;
  }

  vertex_incidence<3>(triangles, num_vertices, topology.vertex_triangle_start, topology.vertex_triangles);
  return topology;
}

}  // namespace weft
