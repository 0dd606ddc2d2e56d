#include "collision/edge_edge.hpp"

#include <algorithm>

#include "collision/point_triangle.hpp"

namespace weft {

namespace {

// Below this value of sin^2 of the angle between the edges the interior solution is not
// trusted (its denominator loses all precision); an endpoint pair is then as close.
constexpr double parallel_sin_squared = 1e-20;

void keep_if_closer(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double s, double t,
                    EdgeEdgeClosest& best) {
  const Vec3 point_a = a0 + s * (a1 - a0);
  const Vec3 point_b = b0 + t * (b1 - b0);
  const double distance = (point_a - point_b).norm();
  if (distance < best.distance) best = {point_a, point_b, s, t, distance};
}

}  // namespace

EdgeEdgeClosest edge_edge_closest(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  const Vec3 da = a1 - a0;
  const Vec3 db = b1 - b0;
  const Vec3 r = a0 - b0;
  const double aa = da.squaredNorm();
  const double bb = db.squaredNorm();
  const double ab = da.dot(db);

  // The four endpoint-to-segment candidates cover every case where a parameter is clamped,
  // including parallel and zero-length edges.
  EdgeEdgeClosest best{a0, b0, 0.0, 0.0, r.norm()};
  keep_if_closer(a0, a1, b0, b1, 0.0, point_segment_parameter(a0, b0, b1), best);
  keep_if_closer(a0, a1, b0, b1, 1.0, point_segment_parameter(a1, b0, b1), best);
  keep_if_closer(a0, a1, b0, b1, point_segment_parameter(b0, a0, a1), 0.0, best);
  keep_if_closer(a0, a1, b0, b1, point_segment_parameter(b1, a0, a1), 1.0, best);

  // Interior candidate: both parameters free, from the 2x2 normal equations
  // aa s - ab t = -da.r, ab s - bb t = -db.r, used only when the edges are clearly not parallel.
  const double denominator = aa * bb - ab * ab;
  if (denominator > parallel_sin_squared * aa * bb && aa > 0.0 && bb > 0.0) {
    const double ar = da.dot(r);
    const double br = db.dot(r);
    const double s = (ab * br - bb * ar) / denominator;
    const double t = (aa * br - ab * ar) / denominator;
    if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) keep_if_closer(a0, a1, b0, b1, s, t, best);
  }
  return best;
}

Vec3 edge_edge_offset(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double aa = da.squaredNorm(), bb = db.squaredNorm(), br = db.dot(r);
  const auto unit = [](double v) { return std::clamp(v, 0.0, 1.0); };
  double s = 0.0, t = 0.0;
  if (!(aa > 0.0)) {
    t = bb > 0.0 ? unit(br / bb) : 0.0;
  } else {
    const double ar = da.dot(r);
    if (!(bb > 0.0)) {
      s = unit(-ar / aa);
    } else {
      const double ab = da.dot(db);
      const double denominator = aa * bb - ab * ab;
      s = denominator > 0.0 ? unit((ab * br - ar * bb) / denominator) : 0.0;
      t = (ab * s + br) / bb;
      if (t < 0.0) {
        t = 0.0;
        s = unit(-ar / aa);
      } else if (t > 1.0) {
        t = 1.0;
        s = unit((ab - ar) / aa);
      }
    }
  }
  return (b0 + t * db) - (a0 + s * da);
}

}  // namespace weft
