#pragma once
// Candidate primitive pairs handed from a broad phase to the narrow phase. Indices refer to one
// combined index space: triangles (3 x n_triangles) and edges (2 x n_edges) over all vertices.

namespace weft {

struct VertexFacePair {
  int vertex;    // combined vertex index
  int triangle;  // combined triangle index; the vertex is not one of its corners

  bool operator==(const VertexFacePair& other) const {
    return vertex == other.vertex && triangle == other.triangle;
  }
  bool operator<(const VertexFacePair& other) const {
    return vertex != other.vertex ? vertex < other.vertex : triangle < other.triangle;
  }
};

struct EdgeEdgePair {
  int edge_a;  // combined edge indices, edge_a < edge_b; the edges share no vertex
  int edge_b;

  bool operator==(const EdgeEdgePair& other) const {
    return edge_a == other.edge_a && edge_b == other.edge_b;
  }
  bool operator<(const EdgeEdgePair& other) const {
    return edge_a != other.edge_a ? edge_a < other.edge_a : edge_b < other.edge_b;
  }
};

}  // namespace weft
