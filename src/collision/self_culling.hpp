#pragma once
// Self-collision culling over a BVH (after Volino and Magnenat-Thalmann 1994, with the
// continuous normal cone of Tang, Curtis, Yoon and Manocha 2009): a region of a surface cannot
// touch itself when
//   1. it is a topological disk (connected, Euler characteristic 1, one boundary loop),
//   2. every triangle normal stays within a cone around one axis for the whole step, so the
//      projection along the axis keeps every triangle's orientation (a local immersion), and
//   3. the boundary projected along the axis stays a simple curve for the whole step,
// because an immersed disk whose boundary is simple is embedded: its projection is one to one.
// The node-pair query then skips the pairs within such a node (its "within node" task).
//
// Continuous version: with edges e1, e2 moving linearly over the step, the normal is
// n(t) = (1-t)^2 n0 + 2t(1-t) m + t^2 n1 with m = (e1(0) x e2(1) + e1(1) x e2(0)) / 2, a
// non-negative combination of n0, m and n1; all three within the cone keep n(t) there.
// The boundary stays simple when every two boundary edges that share no vertex are further
// apart at the start (in projection) than their projected displacements plus the margin.
//
// Culling skips proximity tests inside such regions too: two non-adjacent triangles of a flat
// region within the thickness of each other are not repelled. They cannot cross, which is
// what the collision phase must guarantee.
#include <array>
#include <utility>
#include <vector>

#include "collision/bvh.hpp"
#include "core/math.hpp"

namespace weft {

struct SelfCullingSettings {
  bool enabled = true;
  double max_cone_angle = 1.0471975511965976;  // rad (60 degrees): the widest normal cone culled
};

struct SelfCullingStats {
  int nodes_tested = 0;        // nodes whose cone or contour was examined this step
  int nodes_culled = 0;        // subtrees whose within-node pairs were skipped
  int triangles_culled = 0;    // triangles in those subtrees
};

class SelfCulling {
 public:
  // Topology of every node's triangles (disk or not, boundary edges). Called by update() when
  // the hierarchy was rebuilt since the last call; public for tests.
  void prepare(const Bvh& bvh);

  // Decides which nodes of `bvh` (built or refitted over x_start -> x_end) are culled for this
  // step; `margin` is the proximity distance the query's boxes were inflated by. A node's decision
  // depends on its own triangles' vertices alone: called again on the same hierarchy with the
  // same margin and settings (the collision phase's check of its corrected motion), it decides
  // again only the nodes with a vertex whose motion changed, or that the last call did not reach
  // (under a culled node then), and keeps the others' decisions: the same flags as a fresh call.
  void update(const Bvh& bvh, const Positions& x_start, const Positions& x_end, double margin,
              const SelfCullingSettings& settings = {});

  // Per node: 1 when the pairs within the node can be skipped this step (meaningful only for
  // nodes whose ancestors are not culled). Empty before the first update.
  const std::vector<char>& culled() const { return culled_; }
  const SelfCullingStats& stats() const { return stats_; }
  // Per node: whether its triangles form a disk (after prepare).
  const std::vector<char>& disks() const { return disk_; }

 private:
  // prepare()'s scratch, one a thread: the analysis of one node's triangles, and the boundaries
  // of the disks the thread found ({node, first edge in `found`, edge count} each).
  struct DiskScratch {
    std::vector<std::array<int, 3>> edges;
    std::vector<int> vertices;
    std::vector<int> triangle_parent;
    std::vector<Eigen::Vector2i> boundary;
    std::vector<std::pair<int, int>> ends;
    std::vector<int> edge_parent;
    std::vector<Eigen::Vector2i> found;
    std::vector<std::array<int, 3>> found_nodes;
  };
  static bool disk_boundary(const std::vector<int>& order, const Triangles& triangles, int begin, int end,
                            DiskScratch& scratch);
  bool cone_holds(const std::vector<int>& order, int node, const Vec3& axis, double cos_limit) const;

  int prepared_build_ = -1;           // Bvh::builds() when prepared
  std::vector<int> range_begin_;      // per node: its triangles are triangle_order()[begin, end)
  std::vector<int> range_end_;
  std::vector<char> disk_;            // per node
  std::vector<int> boundary_start_;   // per node: its boundary edges are boundary_[start, start of next)
  std::vector<Eigen::Vector2i> boundary_;
  std::vector<DiskScratch> disk_scratch_;

  // Per step.
  std::vector<Vec3> unit_normals_;    // 3 per triangle: n0, m, n1 normalised (zero when degenerate)
  std::vector<char> degenerate_;      // per triangle: a normal vanished, the cone cannot hold
  std::vector<Vec3> triangle_axes_;   // per triangle: n0 + n1 (twice the area, at both ends)
  std::vector<Vec3> axis_sums_;       // per node: sum of n0 + n1 (area weighted) below it
  std::vector<char> culled_;
  SelfCullingStats stats_;
  // What the last update() decided on, for the next one to tell which nodes it must decide again.
  struct LastUpdate {
    int build = -1;  // Bvh::builds(); -1: none to reuse
    double margin = 0.0;
    double max_cone_angle = 0.0;
    Positions x_start, x_end;
    std::vector<char> reached;  // per node: the walk decided it (no culled ancestor)
    std::vector<char> culled;   // per node: its decision
  };
  LastUpdate last_;
  std::vector<char> changed_vertices_;  // per vertex: its motion differs from last_'s
  std::vector<char> changed_triangles_;
  std::vector<char> changed_nodes_;  // a triangle below has a changed vertex
  std::vector<char> reached_;        // this update's walk

  // Scratch of the contour test, one a thread.
  struct Segment {
    Eigen::Vector2d a, b;          // projected end points at the start of the step
    double reach = 0.0;            // projected displacement bound plus half the margin
    double lower_x = 0.0, upper_x = 0.0, lower_y = 0.0, upper_y = 0.0;
    int u = 0, v = 0;              // vertices
  };
  bool contour_simple(int node, const Vec3& axis, const Positions& x_start, const Positions& x_end,
                      double margin, std::vector<Segment>& segments) const;
  std::vector<std::vector<Segment>> segment_scratch_;
  std::vector<SelfCullingStats> thread_stats_;
  std::vector<int> subtrees_;  // update(): the subtrees walked in parallel
};

// Per triangle of `bvh`: the topmost node flagged in `culled` above it (its culled region), or
// -1. A self walk with these flags skips exactly the pairs of two triangles in one region (the
// pairs within a culled node; append_self_candidates_culled of primitive_queries.hpp). Replaces
// `region`; allocates only to grow it.
void culled_regions(const Bvh& bvh, const std::vector<char>& culled, std::vector<int>& region);

}  // namespace weft
