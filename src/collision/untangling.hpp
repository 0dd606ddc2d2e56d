#pragma once
// Untangling cloth that already passes through itself or another cloth: a global analysis of
// where the surfaces cross (after Baraff, Witkin & Kass 2003, "Untangling cloth"), then a push of
// the part that passed through back to its side.
//
// The cloths are one combined mesh. Each pass finds every edge that pierces a triangle not
// incident to it. For such a crossing, with the triangle's plane between the edge's two ends,
// each end has a side: the vertices reached from it over edges that pierce nothing and that a
// push along the triangle's normal, towards the other end's side, would carry through the
// triangle's mesh. The smaller side is the part that passed through (a flap pushed through a
// sheet, the tip of a pinch, the strip of a sheet laid through another): its vertices move along
// the normal until they are `margin` past the surface they pierce. A side holding a vertex of zero
// inverse mass cannot move; then the other side does. A crossing whose triangle moves with an
// accepted side, or whose ends belong to a pierced triangle, waits for the next pass, so two sides
// of one contour never move at once.
//
// Floating point: the exact check (check/tangle_check.hpp) judges the result apart from this.
#include <vector>

#include "collision/bvh.hpp"
#include "collision/edge_triangle_crossing.hpp"
#include "core/math.hpp"
#include "core/topology.hpp"

namespace weft {

// An edge of the combined mesh through one of its triangles.
struct EdgeThroughTriangle {
  int edge = 0;
  int triangle = 0;
  EdgeTriangleCrossing crossing;
};

// What one pass did.
struct UntanglePass {
  int crossings = 0;          // edges through triangles found at the pass's start
  int sides = 0;              // sides moved
  int moved_vertices = 0;     // vertices given a displacement
  double largest_push = 0.0;  // m
};

struct UntangleSettings {
  // A side larger than this fraction of its mesh's vertices is not moved (the other side is).
  double max_side_fraction = 0.5;
};

class Untangler {
 public:
  UntangleSettings settings;

  // The combined mesh: triangles (3 x n_triangles, indices below num_vertices) and the mesh each
  // vertex belongs to (n_vertices), whose triangles a side is pushed through. Allocates.
  void set_mesh(const Triangles& triangles, const std::vector<int>& vertex_mesh);

  // Every edge through a triangle not incident to it at positions x (3 x n_vertices), sorted by
  // (edge, triangle): the same list on any thread count.
  const std::vector<EdgeThroughTriangle>& find_crossings(const Positions& x);
  const std::vector<EdgeThroughTriangle>& crossings() const { return crossings_; }

  // From the last find_crossings at x: the displacement of each vertex (3 x n_vertices, zero
  // where it stays), moving the sides chosen as above. A vertex of zero inverse mass never moves;
  // `margin` (n_vertices) is how far past the pierced surface a vertex ends.
  UntanglePass plan_pushes(const Positions& x, const Eigen::VectorXd& inverse_mass,
                           const Eigen::VectorXd& margin, Positions& displacement);

  const Eigen::Matrix2Xi& edges() const { return topology_.edges; }

 private:
  // The side of `start` for a crossing with plane (point, normal), pushed towards `towards` (+1:
  // along the normal): into side_ with each vertex's displacement into side_push_. False when it
  // grows past `cap` vertices or holds a vertex that cannot move.
  bool grow_side(int start, const Positions& x, const Eigen::VectorXd& inverse_mass,
                 const Eigen::VectorXd& margin, const EdgeTriangleCrossing& plane, double towards,
                 int pierced_mesh, size_t cap);
  // How far vertex v moves along `direction` to end `margin` past the nearest triangle of
  // `pierced_mesh` that the ray from it crosses within `reach`; negative when it crosses none.
  double push_through(int v, const Positions& x, const Vec3& direction, double reach, double margin,
                      int pierced_mesh);
  int find_root(int v);

  int num_vertices_ = 0;
  Triangles triangles_;
  std::vector<int> vertex_mesh_;
  std::vector<int> mesh_size_;
  MeshTopology topology_;
  std::vector<int> vertex_edge_start_;  // edges around each vertex (vertex_incidence)
  std::vector<int> vertex_edges_;
  Bvh triangle_bvh_;
  Bvh edge_bvh_;
  Triangles edge_entries_;
  BvhQueryBuffers buffers_;
  std::vector<std::vector<EdgeThroughTriangle>> thread_crossings_;
  std::vector<EdgeThroughTriangle> crossings_;
  // plan_pushes' scratch
  std::vector<char> cut_;     // per edge: it pierces a triangle
  std::vector<char> moving_;  // per vertex: in an accepted side
  std::vector<char> frozen_;  // per vertex: a corner of a triangle an accepted side pierces
  std::vector<int> visited_;  // per vertex: the grow_side call that reached it
  int visit_mark_ = 0;
  std::vector<int> side_;  // grow_side's vertices
  std::vector<double> side_push_;
  std::vector<int> best_side_;
  std::vector<double> best_push_;
  std::vector<int> box_triangles_;
  std::vector<int> parent_;                 // union-find over vertices joined by uncut edges
  std::vector<int> piece_size_;             // vertices of each piece, by its root
  std::vector<std::pair<int, int>> order_;  // (smaller piece's size or n + 1, crossing)
};

}  // namespace weft
