#pragma once
// Primitive candidates of the narrow phase, derived from the broad phase's triangle pairs:
// vertex-face pairs (a vertex of one triangle against the other triangle) and edge-edge pairs
// (an edge of one against an edge of the other). Proximity and continuous tests then run on
// these, each primitive pair once however many triangle pairs produced it.
//
// Index spaces. A world numbers the vertices, triangles and edges of all its meshes (cloths and
// obstacle meshes) in one combined space each: mesh m's element i is offsets_m + i, with each
// mesh's offsets the running totals of the meshes before it (see next_offsets()). Candidates
// are written in these combined indices, so pairs within a cloth, between two cloths and
// between a cloth and an obstacle all land in one sorted list. Local edge indices are those of
// the mesh's MeshTopology (core/topology.hpp).
#include <cstdint>
#include <vector>

#include "collision/bvh.hpp"
#include "collision/contact_pairs.hpp"
#include "core/topology.hpp"

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

// A mesh as the candidate stage reads it: its triangles, its topology (for edge indices) and
// where it sits in the combined index spaces. Refers to data the caller keeps alive.
struct CandidateMesh {
  const Triangles& triangles;    // (3 x n_triangles), local vertex indices
  const MeshTopology& topology;  // built from `triangles`
  MeshIndexOffsets offsets;
  const SweptVertexBoxes* boxes = nullptr;  // null: every pair is written
};

// Vertex-face and edge-edge pairs of a step, sorted and free of duplicates.
struct CollisionCandidates {
  std::vector<VertexFacePair> vertex_face;
  std::vector<EdgeEdgePair> edge_edge;
  std::vector<std::uint64_t> sort_keys, sort_scratch;  // sort_candidates' buffers, kept to grow once
  std::vector<VertexFacePair> vertex_face_scratch;     // merge_new_candidates' buffers
  std::vector<EdgeEdgePair> edge_edge_scratch;
  std::vector<std::vector<VertexFacePair>> thread_vertex_faces;  // the appends' per-thread buffers
  std::vector<std::vector<EdgeEdgePair>> thread_edge_edges;

  void clear() {
    vertex_face.clear();
    edge_edge.clear();
  }
};

// What a list of triangle pairs handed to the candidate stage holds, which decides which of its
// pairs write each primitive pair.
//  - `any`: any pairs. Every triangle pair writes every primitive pair it carries: a vertex-face
//    pair once for each triangle around the vertex that meets the face (up to ~6 times), an
//    edge-edge pair up to 4 times; sort_candidates() removes the repeats.
//  - `complete`: the pairs hold the designated triangle pair of every primitive pair whose boxes
//    pass the filter (`mesh.boxes`, required), and only that pair writes it, so each is written
//    once. The designated pair of vertex v against triangle t is (the first triangle around v, in
//    index order, t); of edge e against edge f, (the first triangle at e, the first at f). Within
//    one mesh these two triangles may share a vertex, so self pairs must come from a query that
//    keeps shared-vertex pairs (SharedVertexPairs::keep). A triangle's swept box holds its
//    corners' boxes, so a query over triangle boxes inflated by gap/2 (find_self_pairs keeping
//    shared-vertex pairs, no culling; find_pairs_between) finds the designated pair of every
//    primitive pair within the gap; so does find_pairs_of (keeping them) for every primitive pair
//    with a vertex of a listed triangle's. Self candidates of a mesh with non-manifold edges are
//    written as with `any` (its topology keeps only two triangles an edge).
enum class TrianglePairList { any, complete };

// Adds the candidates of triangle pairs within one mesh (from find_self_pairs) to `candidates`,
// which stays sorted and duplicate-free: for each pair, every vertex of one triangle that is not
// a corner of the other against that other, and every edge of one against every edge of the
// other that shares no vertex with it. Allocates only when `candidates` must grow.
void add_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                         CollisionCandidates& candidates, TrianglePairList list = TrianglePairList::any);

// The same for triangle pairs between two different meshes (from find_pairs_between, a in
// `first`, b in `second`), where no vertex is shared.
void add_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                            const CandidateMesh& second, CollisionCandidates& candidates,
                            TrianglePairList list = TrianglePairList::any);

// The same two without the final sort: many meshes append, then sort_candidates() once.
void append_self_candidates(const std::vector<TrianglePair>& pairs, const CandidateMesh& mesh,
                            CollisionCandidates& candidates, TrianglePairList list = TrianglePairList::any);
void append_candidates_between(const std::vector<TrianglePair>& pairs, const CandidateMesh& first,
                               const CandidateMesh& second, CollisionCandidates& candidates,
                               TrianglePairList list = TrianglePairList::any);
// Sorts both lists (by their first index, then their second) and removes duplicates.
void sort_candidates(CollisionCandidates& candidates);

// Both sorted and duplicate-free: drops from `added` the pairs `all` already holds, then merges
// what is left into `all`, which stays sorted and duplicate-free; `added` keeps the new pairs.
void merge_new_candidates(CollisionCandidates& all, CollisionCandidates& added);

}  // namespace weft
