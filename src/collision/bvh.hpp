#pragma once
// Bounding-volume hierarchy of axis-aligned boxes over the triangles of one mesh: the broad
// phase of collision detection. Each triangle's box is swept over the step (the union of its
// boxes at x_start and x_end) and inflated by a margin (the cloth thickness), so one query per
// step finds every pair that could come into proximity or collide during the step. The same
// hierarchy holds a mesh's vertices or edges as degenerate triangles (v, v, v) and (a, b, b)
// (primitive_queries.hpp); "triangle" below then means such an entry.
//
// Nodes live in one flat array in depth-first preorder: a node's left child is the next node,
// its right child is stored, and `next` is the first node after its subtree, so a box query
// walks the array without a stack. The tree is built top-down once (binned SAH), refitted
// every step, and rebuilt when `needs_rebuild()` says refitting has made it too loose.
//
// Pair queries walk two hierarchies (or one against itself) in parallel with OpenMP
// (bvh_traversal.hpp); the broad phase over primitives (primitive_queries.hpp) is built on them.
#include <limits>
#include <vector>

#include "core/math.hpp"

namespace weft {

// Closed axis-aligned box: boxes that only touch overlap. Default-constructed it is empty.
struct Aabb {
  Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 upper = Vec3::Constant(-std::numeric_limits<double>::infinity());

  void grow(const Vec3& point) {
    lower = lower.cwiseMin(point);
    upper = upper.cwiseMax(point);
  }
  void grow(const Aabb& box) {
    lower = lower.cwiseMin(box.lower);
    upper = upper.cwiseMax(box.upper);
  }
  bool overlaps(const Aabb& other) const {
    return lower.x() <= other.upper.x() && other.lower.x() <= upper.x() && lower.y() <= other.upper.y() &&
           other.lower.y() <= upper.y() && lower.z() <= other.upper.z() && other.lower.z() <= upper.z();
  }
  bool empty() const { return !(lower.array() <= upper.array()).all(); }
  // Surface area of the box; 0 when empty.
  double surface_area() const;
};

// One node of the flat hierarchy (64 bytes).
struct BvhNode {
  Aabb box;        // encloses the swept, inflated boxes of every triangle below
  int first = 0;   // leaf: first slot of its triangles in Bvh::triangle_order(); inner: unused
  int count = 0;   // leaf: number of triangles (>= 1); inner: 0
  int right = -1;  // inner: index of the right child (the left child is this index + 1); leaf: -1
  int next = 0;    // index of the first node after this subtree (nodes.size() at the end)

  bool is_leaf() const { return count > 0; }
};

struct BvhSettings {
  int max_leaf_size = 4;       // a node with at most this many triangles becomes a leaf
  int sah_bins = 16;           // candidate split planes per node for the surface area heuristic
  double rebuild_ratio = 2.0;  // needs_rebuild() once cost() exceeds this times cost_at_build()
};

class Bvh {
 public:
  // Builds the hierarchy over `triangles` (3 x n_triangles, indices into the positions) with
  // each triangle's box swept from x_start to x_end and inflated by `margin` on every side.
  // Copies the triangles. Throws std::invalid_argument on mismatched sizes, an index out of
  // range or a negative margin.
  void build(const Positions& x_start, const Positions& x_end, const Triangles& triangles, double margin,
             const BvhSettings& settings = {});
  // Static positions: boxes around x only.
  void build(const Positions& x, const Triangles& triangles, double margin,
             const BvhSettings& settings = {}) {
    build(x, x, triangles, margin, settings);
  }

  // Recomputes every box bottom-up for new positions, keeping the tree; allocates nothing.
  // Throws std::invalid_argument if the vertex count differs from the one at build.
  void refit(const Positions& x_start, const Positions& x_end, double margin);
  void refit(const Positions& x, double margin) { refit(x, x, margin); }
  // refit() when only the vertices flagged in `moved` (per vertex) have changed since the last
  // build or refit, with the same margin: the boxes of the triangles they touch and of the nodes
  // above those are recomputed, the others kept. The same boxes and cost() as refit().
  void refit_moved(const Positions& x_start, const Positions& x_end, double margin,
                   const std::vector<char>& moved);

  // Tree quality: the sum of the surface areas of all nodes over the root's, roughly the
  // expected number of nodes a small query box visits. cost() is the value now, cost_at_build()
  // just after the last build; their ratio grows as refits loosen the tree.
  double cost() const { return cost_; }
  double cost_at_build() const { return cost_at_build_; }
  double degradation() const { return cost_at_build_ > 0.0 ? cost_ / cost_at_build_ : 1.0; }
  bool needs_rebuild() const { return degradation() > settings_.rebuild_ratio; }

  int num_triangles() const { return static_cast<int>(triangles_.cols()); }
  int num_vertices() const { return num_vertices_; }
  const Triangles& triangles() const { return triangles_; }
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  // Each node's box's surface area (n_nodes), from the last build or refit.
  const std::vector<double>& node_areas() const { return node_areas_; }
  // Triangle indices in leaf order: leaf n holds triangle_order()[first, first + count).
  const std::vector<int>& triangle_order() const { return triangle_order_; }
  // Swept, inflated box of each triangle (n_triangles), from the last build or refit.
  const std::vector<Aabb>& triangle_boxes() const { return triangle_boxes_; }
  // The same boxes in leaf order (leaf n's are leaf_boxes()[first, first + count)): the pair
  // queries read a leaf's boxes from contiguous memory instead of through triangle_order().
  const std::vector<Aabb>& leaf_boxes() const { return leaf_boxes_; }
  const BvhSettings& settings() const { return settings_; }
  // How many times build() has run: data kept per node elsewhere is stale when this changed.
  int builds() const { return builds_; }

 private:
  void compute_triangle_boxes(const Positions& x_start, const Positions& x_end, double margin);
  Aabb triangle_box(int t, const Positions& x_start, const Positions& x_end, double margin) const;
  void build_nodes();
  void refit_nodes();
  void refit_node(int i);  // node i's box (and a leaf's boxes in leaf order) from below, and its area
  void sum_cost();         // cost_ from node_areas_

  BvhSettings settings_;
  Triangles triangles_;  // copy of the mesh's triangles (3 x n_triangles)
  int num_vertices_ = 0;
  std::vector<Aabb> triangle_boxes_;  // (n_triangles)
  std::vector<Aabb> leaf_boxes_;      // (n_triangles) triangle_boxes_ in triangle_order_
  std::vector<int> triangle_order_;   // (n_triangles)
  std::vector<BvhNode> nodes_;        // depth-first preorder; empty when there are no triangles
  // build_nodes' scratch, kept so that a rebuild during a steady-state step allocates nothing.
  struct BuildRange {
    int begin;
    int end;
    int parent_of_right;  // the parent whose right child this range becomes, or -1
  };
  std::vector<Vec3> centroids_;
  std::vector<Aabb> bin_boxes_;
  std::vector<int> bin_counts_;
  std::vector<double> right_areas_;
  std::vector<BuildRange> ranges_;
  std::vector<double> node_areas_;  // per node, by refit_node
  // refit_nodes' scratch: the subtrees swept in parallel, the nodes above them.
  std::vector<int> subtrees_;
  std::vector<int> upper_nodes_;
  std::vector<char> moved_entries_;  // refit_moved's scratch: per triangle, per node
  std::vector<char> moved_nodes_;
  double cost_ = 0.0;
  double cost_at_build_ = 0.0;
  int builds_ = 0;
};

// A pair of triangles whose boxes overlap: `a` from the first hierarchy, `b` from the second;
// in a self query both come from the same mesh and a < b.
struct TrianglePair {
  int a;
  int b;

  bool operator==(const TrianglePair& other) const { return a == other.a && b == other.b; }
  bool operator!=(const TrianglePair& other) const { return !(*this == other); }
  bool operator<(const TrianglePair& other) const { return a != other.a ? a < other.a : b < other.b; }
};

// Scratch space of the pair walks, kept by the caller between steps so that steady-state
// queries do not allocate: the node-pair tasks handed to threads and each thread's traversal
// stack.
struct BvhQueryBuffers {
  std::vector<TrianglePair> tasks;                       // node pairs (a == b: "within node a")
  std::vector<TrianglePair> next_tasks;                  // scratch while splitting tasks
  std::vector<std::vector<TrianglePair>> thread_stacks;  // node pairs still to visit, per thread
};

// Triangles whose boxes overlap `box` (picking, analytic colliders), sorted. Single-threaded,
// no stack: replaces the contents of `triangles` and allocates only if it must grow.
void find_triangles_in_box(const Bvh& bvh, const Aabb& box, std::vector<int>& triangles);

}  // namespace weft
