#pragma once
// The collision broad phase at the level of primitives: each vertex's swept box against a
// hierarchy of triangle boxes (vertex-face pairs) and edge boxes against edge boxes (edge-edge
// pairs), written as CollisionCandidates in the world's combined index spaces.
//
// Why not triangle pairs: a flat sheet's triangles all touch their neighbours' inflated boxes,
// so a triangle-pair query hands tens of thousands of pairs to a stage that opens each into 6
// vertex-face and 9 edge-edge pairs, only to drop nearly all of them. Querying the primitives
// themselves visits each primitive pair whose boxes come within the gap once, and nothing else.
//
// The contract (the one CollisionPhase::verify_motion relies on): with `boxes` the vertices'
// swept boxes and gap g, every vertex-face pair (vertex not a corner of the face) and every
// edge-edge pair (no common vertex) whose boxes (the union of its vertices' boxes) are within g
// along every coordinate axis, and not more than g |n|_1 apart along the direction n between
// the primitives' closest points at their boxes' centres, is written; no other pair is. The
// hierarchies' boxes must be the swept boxes inflated by g / 2 (a vertex's, an edge's, a
// triangle's), so that two entries' boxes overlap exactly when their raw boxes are within g.
// A vertex that no triangle uses is never written (no triangle carries it).
#include <vector>

#include "collision/bvh.hpp"
#include "collision/candidates.hpp"
#include "core/topology.hpp"

namespace weft {

// Entries of a hierarchy over points or segments. Bvh takes three vertex indices an entry and
// boxes them, so vertex v is the entry (v, v, v) and the edge (a, b) is (a, b, b): their boxes
// are the point's and the segment's. Indices are offset into the combined vertex space.
Triangles point_entries(int vertex_offset, int num_vertices);
Triangles segment_entries(const Eigen::Matrix2Xi& edges, int vertex_offset);

// A mesh as the primitive queries read it: its triangles and topology, where it sits in the
// combined index spaces, and its three hierarchies (entries numbered as its local triangles,
// vertices and edges, built over combined positions with margin gap / 2).
struct PrimitiveMesh {
  const Triangles& triangles;    // (3 x n_triangles), local vertex indices
  const MeshTopology& topology;  // built from `triangles`
  MeshIndexOffsets offsets;
  const Bvh& triangle_bvh;
  const Bvh& vertex_bvh;  // over point_entries(offsets.vertex, n_vertices)
  const Bvh& edge_bvh;    // over segment_entries(topology.edges, offsets.vertex)
};

// Appends the candidates of a mesh against itself (unsorted: sort_candidates() once after all
// appends). Runs over the OpenMP threads; the set written does not depend on their number.
void append_self_primitive_candidates(const PrimitiveMesh& mesh, const SweptVertexBoxes& boxes,
                                      BvhQueryBuffers& buffers, CollisionCandidates& candidates);

// Each vertex and each edge of a mesh given to one triangle that holds it (its first in the
// topology's lists), so that a walk over triangle pairs meets each primitive pair once, through
// the owners of its two primitives (the representative triangles of Curtis, Tamstorf and
// Manocha 2008). A vertex no triangle uses has no owner.
struct OwnedPrimitives {
  std::vector<int> vertex_start;  // (n_triangles + 1): triangle t owns vertices[vertex_start[t] ..)
  std::vector<int> vertices;      // local vertex indices, by owner
  std::vector<int> edge_start;    // (n_triangles + 1): triangle t owns edges[edge_start[t] ..)
  std::vector<int> edges;         // local edge indices, by owner
};
OwnedPrimitives owned_primitives(const MeshTopology& topology, int num_triangles);

// The self candidates of a mesh with self-collision culling (self_culling.hpp): one walk of its
// triangle hierarchy, each pair of triangles whose boxes overlap testing the primitives they own
// against each other with the filter above, and the pairs within a node flagged in `culled`
// skipped whole, so a culled region costs nothing. So a pair is written exactly when the full
// query above writes it and no culled node holds both its primitives' owners (a vertex-face
// pair: the vertex's owner and the face). With `within`, only pairs within those nodes are
// walked (the regions whose culling stopped holding). Unsorted, as above.
void append_self_candidates_culled(const PrimitiveMesh& mesh, const OwnedPrimitives& owned,
                                   const SweptVertexBoxes& boxes, const std::vector<char>& culled,
                                   const std::vector<int>* within, BvhQueryBuffers& buffers,
                                   CollisionCandidates& candidates);

// Appends the candidates between two different meshes: first's vertices against second's
// triangles and the other way round, first's edges against second's. Unsorted, as above.
void append_primitive_candidates_between(const PrimitiveMesh& first, const PrimitiveMesh& second,
                                         const SweptVertexBoxes& boxes, BvhQueryBuffers& buffers,
                                         CollisionCandidates& candidates);

// The primitives of a mesh that touch moved vertices, in local indices: the vertices, the
// triangles with a moved corner and the edges with a moved end.
struct MovedPrimitives {
  std::vector<int> vertices;
  std::vector<int> triangles;
  std::vector<int> edges;

  bool empty() const { return vertices.empty(); }
};

// Lists the primitives of `mesh` touching the vertices flagged in `moved` (combined vertex
// flags). Allocates only to grow.
void list_moved_primitives(const PrimitiveMesh& mesh, const std::vector<char>& moved,
                           MovedPrimitives& listed);

// The re-query of CollisionPhase::verify_motion: appends every candidate of `mesh` against
// `other` (the same mesh when `self`) that has a vertex of `listed`, queried with the boxes
// the hierarchies were last refitted with. Pairs without a listed vertex are not written; they
// are candidates already if their boxes did not change. Runs over the OpenMP threads, each with
// its box query's scratch in `thread_scratch`. Unsorted and possibly with repeats: sort_candidates()
// after.
void append_moved_primitive_candidates(const PrimitiveMesh& mesh, const MovedPrimitives& listed,
                                       const PrimitiveMesh& other, bool self, const SweptVertexBoxes& boxes,
                                       std::vector<std::vector<int>>& thread_scratch,
                                       CollisionCandidates& candidates);

}  // namespace weft
