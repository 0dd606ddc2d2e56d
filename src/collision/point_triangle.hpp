#pragma once
// Closest point of a triangle to a point, robust for needle and zero-area triangles.
#include "core/math.hpp"

namespace weft {

struct PointTriangleClosest {
  Vec3 closest;      // closest point of the closed triangle
  Vec3 barycentric;  // weights of a, b, c giving `closest`: each in [0, 1], summing to 1
  double distance;   // |p - closest|
};

// Closest point of triangle (a, b, c) to p. A triangle whose area is negligible against its
// longest edge squared is treated as its three edges, so a needle or a point is handled too.
PointTriangleClosest point_triangle_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Closest point of segment (a, b) to p: returns the parameter s in [0, 1] of a + s (b - a);
// s = 0 when the segment has zero length.
double point_segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b);

}  // namespace weft
