#pragma once
// Exact triangle-triangle intersection check: the judge of the collision code, written apart
// from it (no shared helpers, no shared filters), for tests, for every run's tangle check
// (tangle_check.hpp) and for checking a recording after the fact.
//
// Triangles are closed sets: two that only touch (a shared point, a vertex on a face, an edge
// crossing an edge) intersect, and so do coplanar triangles that overlap. Every decision is
// made by the signs of orient2d / orient3d determinants, evaluated in double with a forward
// error bound and, when the bound cannot decide, exactly with floating-point expansions
// (doubles are dyadic rationals, so sums and products of them have exact expansions). The
// result is therefore exact for any finite input whose products neither overflow nor
// underflow (coordinates roughly within 1e-90 .. 1e90 in magnitude, or exactly 0).
// Degenerate triangles (collinear or repeated corners) are handled as the segments or points
// they are.
#include <vector>

#include "core/math.hpp"

namespace weft {

// Sign (-1, 0, +1) of det[a - d; b - d; c - d]: +1 when d lies below the plane through a, b, c,
// "below" seen from the side where a, b, c run counter-clockwise; 0 when the four are coplanar.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Sign (-1, 0, +1) of det[a - c; b - c]: +1 when a, b, c run counter-clockwise.
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

// Whether the closed triangles (p0, p1, p2) and (q0, q1, q2) share at least one point.
bool triangles_intersect(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& q0, const Vec3& q1,
                         const Vec3& q2);

// One mesh to check; refers to data the caller keeps alive.
struct CheckedMesh {
  const Positions* positions = nullptr;  // (3 x n_vertices)
  const Triangles* triangles = nullptr;  // (3 x n_triangles)
  bool obstacle = false;  // pairs of two obstacle triangles (colliders among themselves) are not tested
};

// A pair of intersecting triangles, (mesh_a, triangle_a) < (mesh_b, triangle_b).
struct TriangleIntersection {
  int mesh_a;
  int triangle_a;
  int mesh_b;
  int triangle_b;

  bool operator==(const TriangleIntersection& other) const {
    return mesh_a == other.mesh_a && triangle_a == other.triangle_a && mesh_b == other.mesh_b &&
           triangle_b == other.triangle_b;
  }
  bool operator<(const TriangleIntersection& other) const;
};

// Every intersecting pair of triangles among `meshes`, sorted, by the standard definition (the
// one of CGAL's self-intersection test): two triangles of one mesh that share a vertex intersect
// when they meet anywhere other than at that vertex, two that share a side when they meet
// anywhere other than along that side (they overlap in their common plane), a triangle listed
// twice always; triangles of different meshes share nothing. Pairs of two obstacle triangles
// (of one obstacle mesh or of two) are not tested. Candidates are the pairs whose bounding
// boxes overlap, from a hierarchy over the boxes (box_tree.hpp). Throws std::invalid_argument on a
// null mesh, an index out of range or a coordinate that is not finite.
std::vector<TriangleIntersection> find_triangle_intersections(const std::vector<CheckedMesh>& meshes);
std::vector<TriangleIntersection> find_triangle_intersections(const Positions& positions,
                                                              const Triangles& triangles);

// The same by testing every pair (quadratic): the reference the box tree is tested against.
std::vector<TriangleIntersection> find_triangle_intersections_brute_force(
    const std::vector<CheckedMesh>& meshes);

}  // namespace weft
