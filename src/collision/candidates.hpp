#pragma once
// Primitive candidates of the narrow phase, as the broad phase (primitive_queries.hpp) writes
// them: vertex-face pairs (a vertex against a triangle it is not a corner of) and edge-edge
// pairs (two edges without a common vertex), sorted and free of duplicates, so that proximity
// and continuous tests run on each primitive pair once.
//
// Index spaces. A world numbers the vertices, triangles and edges of all its meshes (cloths and
// obstacle meshes) in one combined space each: mesh m's element i is offsets_m + i, with each
// mesh's offsets the running totals of the meshes before it (see next_offsets()). Candidates
// are written in these combined indices, so pairs within a cloth, between two cloths and
// between a cloth and an obstacle all land in one sorted list. Local edge indices are those of
// the mesh's MeshTopology (core/topology.hpp).
#include <cstdint>
#include <vector>

#include "collision/contact_pairs.hpp"
#include "core/math.hpp"

namespace weft {

// Where one mesh's vertices, triangles and edges start in the world's combined index spaces.
struct MeshIndexOffsets {
  int vertex = 0;
  int triangle = 0;
  int edge = 0;
};

// The offsets of the mesh after one at `offsets` with these element counts.
MeshIndexOffsets next_offsets(const MeshIndexOffsets& offsets, int num_vertices, int num_triangles,
                              int num_edges);

// Per-vertex boxes swept over the step, in combined vertex indices (3 x n_vertices each):
// a primitive pair whose boxes (the union of its vertices' boxes) stay more than `gap` apart
// can neither come within the thickness nor collide, and is not written.
struct SweptVertexBoxes {
  const Positions& lower;
  const Positions& upper;
  double gap;
};

// Vertex-face and edge-edge pairs of a step, sorted and free of duplicates.
struct CollisionCandidates {
  std::vector<VertexFacePair> vertex_face;
  std::vector<EdgeEdgePair> edge_edge;
  std::vector<std::uint64_t> sort_keys, sort_scratch;  // sort_candidates' buffers, kept to grow once
  std::vector<VertexFacePair> vertex_face_scratch;     // merge_new_candidates' buffers
  std::vector<EdgeEdgePair> edge_edge_scratch;
  std::vector<std::vector<VertexFacePair>> thread_vertex_faces;  // the queries' per-thread buffers
  std::vector<std::vector<EdgeEdgePair>> thread_edge_edges;

  void clear() {
    vertex_face.clear();
    edge_edge.clear();
  }
};

// Sorts both lists (by their first index, then their second) and removes duplicates.
void sort_candidates(CollisionCandidates& candidates);

// Both sorted and duplicate-free: drops from `added` the pairs `all` already holds, then merges
// what is left into `all`, which stays sorted and duplicate-free; `added` keeps the new pairs.
void merge_new_candidates(CollisionCandidates& all, CollisionCandidates& added);

}  // namespace weft
