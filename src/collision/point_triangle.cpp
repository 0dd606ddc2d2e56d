#include "collision/point_triangle.hpp"

#include <algorithm>

namespace weft {

namespace {

// Below this ratio of |normal|^2 to (longest edge^2)^2 the triangle is handled as its edges:
// sin^2 of its smallest angle is then about 1e-24, far below what projection can resolve.
constexpr double degenerate_area_ratio = 1e-24;

}  // namespace

double point_segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 e = b - a;
  const double length_squared = e.squaredNorm();
  if (!(length_squared > 0.0)) return 0.0;
  return std::clamp((p - a).dot(e) / length_squared, 0.0, 1.0);
}

PointTriangleClosest point_triangle_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 normal = ab.cross(ac);
  const double normal_squared = normal.squaredNorm();
  const double longest_squared = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});

  // Interior: project onto the plane; the signed sub-areas over |n|^2 are the barycentrics.
  if (normal_squared > degenerate_area_ratio * longest_squared * longest_squared) {
    const Vec3 projected = p - (normal.dot(p - a) / normal_squared) * normal;
    const double wa = normal.dot((b - projected).cross(c - projected)) / normal_squared;
    const double wb = normal.dot((c - projected).cross(a - projected)) / normal_squared;
    const double wc = 1.0 - wa - wb;
    if (wa >= 0.0 && wb >= 0.0 && wc >= 0.0) {
      const Vec3 closest = wa * a + wb * b + wc * c;
      return {closest, Vec3(wa, wb, wc), (p - closest).norm()};
    }
  }

  // Outside (or degenerate): the closest point lies on one of the three edges.
  const Vec3* corners[3] = {&a, &b, &c};
  PointTriangleClosest best{a, Vec3(1.0, 0.0, 0.0), (p - a).norm()};
  for (int k = 0; k < 3; ++k) {
    const Vec3& from = *corners[k];
    const Vec3& to = *corners[(k + 1) % 3];
    const double s = point_segment_parameter(p, from, to);
    const Vec3 closest = from + s * (to - from);
    const double distance = (p - closest).norm();
    if (distance < best.distance) {
      best.closest = closest;
      best.barycentric.setZero();
      best.barycentric[k] = 1.0 - s;
      best.barycentric[(k + 1) % 3] = s;
      best.distance = distance;
    }
  }
  return best;
}

}  // namespace weft
