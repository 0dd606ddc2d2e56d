#pragma once
// Candidate primitive pairs handed from a broad phase to the narrow phase. Indices refer to one
// combined index space: triangles (3 x n_triangles) and edges (2 x n_edges) over all vertices.

namespace weft {

struct VertexFacePair {
  int vertex;
  int triangle;
};

struct EdgeEdgePair {
  int edge_a;
  int edge_b;
};

}  // namespace weft
