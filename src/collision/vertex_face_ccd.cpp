#include "collision/vertex_face_ccd.hpp"

#include <algorithm>
#include <cmath>

#include "collision/coplanarity_cubic.hpp"
#include "collision/point_triangle.hpp"

namespace weft {

namespace {

// A triangle normal shorter than this fraction of the longest edge squared is not trusted.
constexpr double degenerate_normal_ratio = 1e-12;

// Unit normal at the contact: the triangle's normal when it has one, else the direction from the
// closest point, else one perpendicular to the relative motion; turned to face the vertex's
// side, i.e. against the relative displacement over the step (or towards the start offset).
Vec3 contact_normal(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& closest,
                    const Vec3& relative_motion, const Vec3& start_offset) {
  Vec3 normal = (b - a).cross(c - a);
  const double longest_squared =
      std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  if (!(normal.norm() > degenerate_normal_ratio * longest_squared)) {
    normal = p - closest;
    if (!(normal.norm() > 0.0)) normal = relative_motion;
    if (!(normal.norm() > 0.0)) normal = start_offset;
    if (!(normal.norm() > 0.0)) normal = Vec3::UnitZ();
  }
  normal.normalize();
  const double approach = normal.dot(relative_motion);
  if (approach > 0.0 || (approach == 0.0 && normal.dot(start_offset) < 0.0)) normal = -normal;
  return normal;
}

}  // namespace

std::optional<VertexFaceImpact> vertex_face_ccd(const Vec3& p_start, const Vec3& a_start, const Vec3& b_start,
                                                const Vec3& c_start, const Vec3& p_end, const Vec3& a_end,
                                                const Vec3& b_end, const Vec3& c_end, double eta) {
  const Vec3 dp = p_end - p_start;
  const Vec3 da = a_end - a_start;
  const Vec3 db = b_end - b_start;
  const Vec3 dc = c_end - c_start;

  // Coplanarity (BFA eq. 6 with x1 = a): (x21 + t v21) x (x31 + t v31) . (x41 + t v41) = 0.
  const CoplanarityCubic cubic =
      coplanarity_cubic(b_start - a_start, db - da, c_start - a_start, dc - da, p_start - a_start, dp - da);
  if (!may_vanish(cubic)) return std::nullopt;

  // The vertex-triangle distance changes no faster than the largest relative vertex speed.
  const double lipschitz = std::max({(dp - da).norm(), (dp - db).norm(), (dp - dc).norm()});
  const auto distance_at = [&](double t) {
    return point_triangle_closest(p_start + t * dp, a_start + t * da, b_start + t * db, c_start + t * dc)
        .distance;
  };
  if (!may_come_within(distance_at(0.0), distance_at(1.0), lipschitz, eta)) return std::nullopt;

  std::array<TimeInterval, 3> intervals;
  const int count = near_coplanar_intervals(cubic, intervals);
  if (count == 0) return std::nullopt;

  // Proximity test over each coplanar interval, earliest first.
  for (int k = 0; k < count; ++k) {
    const double t = earliest_proximity(distance_at, intervals[k], eta, lipschitz);
    if (t < 0.0) continue;
    const Vec3 p = p_start + t * dp;
    const Vec3 a = a_start + t * da;
    const Vec3 b = b_start + t * db;
    const Vec3 c = c_start + t * dc;
    const PointTriangleClosest closest = point_triangle_closest(p, a, b, c);
    const Vec3& w = closest.barycentric;
    const Vec3 relative_motion = dp - (w[0] * da + w[1] * db + w[2] * dc);
    const Vec3 start_offset = p_start - (w[0] * a_start + w[1] * b_start + w[2] * c_start);
    return VertexFaceImpact{t, w, contact_normal(p, a, b, c, closest.closest, relative_motion, start_offset),
                            closest.distance};
  }
  return std::nullopt;
}

}  // namespace weft
