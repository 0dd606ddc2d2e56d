#include "collision/edge_edge_ccd.hpp"

#include <algorithm>
#include <cmath>

#include "collision/coplanarity_cubic.hpp"
#include "collision/edge_edge.hpp"

namespace weft {

namespace {

// sin of the angle between the edges below which their cross product is not a usable normal.
constexpr double parallel_sin = 1e-10;

// Unit normal at the contact: the edges' cross product when they are not parallel, else the
// direction between the closest points, else one perpendicular to edge a; turned to face edge
// a's side, i.e. against the relative displacement over the step (or towards the start offset).
Vec3 contact_normal(const Vec3& edge_a, const Vec3& edge_b, const Vec3& gap, const Vec3& relative_motion,
                    const Vec3& start_offset) {
  Vec3 normal = edge_a.cross(edge_b);
  if (!(normal.norm() > parallel_sin * edge_a.norm() * edge_b.norm())) {
    normal = gap;
    // Perpendicular to edge a, in the plane of edge a and the motion when there is one.
    const Vec3 along = edge_a.norm() > 0.0 ? Vec3(edge_a.normalized()) : Vec3::Zero();
    if (!(normal.norm() > 0.0)) normal = relative_motion - relative_motion.dot(along) * along;
    if (!(normal.norm() > 0.0)) normal = start_offset - start_offset.dot(along) * along;
    if (!(normal.norm() > 0.0)) normal = along.unitOrthogonal();
    if (!(normal.norm() > 0.0)) normal = Vec3::UnitZ();
  }
  normal.normalize();
  const double approach = normal.dot(relative_motion);
  if (approach > 0.0 || (approach == 0.0 && normal.dot(start_offset) < 0.0)) normal = -normal;
  return normal;
}

}  // namespace

std::optional<EdgeEdgeImpact> edge_edge_ccd(const Vec3& a0_start, const Vec3& a1_start, const Vec3& b0_start,
                                            const Vec3& b1_start, const Vec3& a0_end, const Vec3& a1_end,
                                            const Vec3& b0_end, const Vec3& b1_end, double eta) {
  const Vec3 da0 = a0_end - a0_start;
  const Vec3 da1 = a1_end - a1_start;
  const Vec3 db0 = b0_end - b0_start;
  const Vec3 db1 = b1_end - b1_start;

  // Coplanarity (BFA eq. 6 with x1 = a0, x2 = a1, x3 = b0, x4 = b1):
  // (x21 + t v21) x (x43 + t v43) . (x31 + t v31) = 0.
  const CoplanarityCubic cubic = coplanarity_cubic(a1_start - a0_start, da1 - da0, b1_start - b0_start,
                                                   db1 - db0, b0_start - a0_start, db0 - da0);
  if (!may_vanish(cubic)) return std::nullopt;

  // The edge-edge distance changes no faster than the largest relative endpoint speed.
  const double lipschitz =
      std::max({(da0 - db0).norm(), (da0 - db1).norm(), (da1 - db0).norm(), (da1 - db1).norm()});
  const auto distance_at = [&](double t) {
    return edge_edge_closest(a0_start + t * da0, a1_start + t * da1, b0_start + t * db0, b1_start + t * db1)
        .distance;
  };
  if (!may_come_within(distance_at(0.0), distance_at(1.0), lipschitz, eta)) return std::nullopt;

  std::array<TimeInterval, 3> intervals;
  const int count = near_coplanar_intervals(cubic, intervals);
  if (count == 0) return std::nullopt;

  // Proximity test over each coplanar interval, earliest first.
  for (int k = 0; k < count; ++k) {
    const double time = earliest_proximity(distance_at, intervals[k], eta, lipschitz);
    if (time < 0.0) continue;
    const Vec3 a0 = a0_start + time * da0;
    const Vec3 a1 = a1_start + time * da1;
    const Vec3 b0 = b0_start + time * db0;
    const Vec3 b1 = b1_start + time * db1;
    const EdgeEdgeClosest closest = edge_edge_closest(a0, a1, b0, b1);
    const double s = closest.s;
    const double t = closest.t;
    const Vec3 relative_motion = (1.0 - s) * da0 + s * da1 - (1.0 - t) * db0 - t * db1;
    const Vec3 start_offset = (1.0 - s) * a0_start + s * a1_start - (1.0 - t) * b0_start - t * b1_start;
    const Vec3 normal =
        contact_normal(a1 - a0, b1 - b0, closest.point_a - closest.point_b, relative_motion, start_offset);
    return EdgeEdgeImpact{time, s, t, normal, closest.distance};
  }
  return std::nullopt;
}

}  // namespace weft
