#pragma once
// Where a segment passes through a triangle: the primitive of untangling (untangling.hpp), which
// cuts a surface along the edges that pierce another. Floating point with a relative tolerance;
// the exact check (check/intersection_check.hpp) judges the result apart from it.
#include <optional>

#include "core/math.hpp"

namespace weft {

struct EdgeTriangleCrossing {
  double s = 0.0;              // the crossing is a + s (b - a), s in (0, 1)
  Vec3 point = Vec3::Zero();   // m, the crossing point
  Vec3 normal = Vec3::Zero();  // unit normal of the triangle, (q - p) x (r - p) normalised
};

// The point where segment (a, b) crosses triangle (p, q, r), when it does: a and b strictly on
// opposite sides of the triangle's plane, and the crossing point inside the closed triangle (on
// an edge or a corner included). An end on the plane, a segment in it and a triangle without
// area count as no crossing.
std::optional<EdgeTriangleCrossing> edge_triangle_crossing(const Vec3& a, const Vec3& b, const Vec3& p,
                                                           const Vec3& q, const Vec3& r);

}  // namespace weft
