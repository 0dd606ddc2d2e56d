#include "collision/edge_triangle_crossing.hpp"

#include <cmath>

namespace weft {

std::optional<EdgeTriangleCrossing> edge_triangle_crossing(const Vec3& a, const Vec3& b, const Vec3& p,
                                                           const Vec3& q, const Vec3& r) {
  const Vec3 n = (q - p).cross(r - p);
  const double area2 = n.norm();
  const double scale = std::max({(q - p).norm(), (r - p).norm(), (b - a).norm()});
  if (!(area2 > 1e-14 * scale * scale)) return std::nullopt;  // a needle or a point: no interior
  const Vec3 unit = n / area2;
  // Signed heights of the edge's ends above the plane.
  const double da = unit.dot(a - p);
  const double db = unit.dot(b - p);
  const double tolerance = 1e-12 * scale;
  if (!((da > tolerance && db < -tolerance) || (da < -tolerance && db > tolerance))) return std::nullopt;
  const double s = da / (da - db);
  const Vec3 x = a + s * (b - a);
  // Inside: the crossing point on the inner side of each of the three edges, or on an edge (an
  // edge through another edge crosses both triangles beside it).
  const double edge_tolerance = 1e-12 * scale * scale;
  if (unit.dot((q - p).cross(x - p)) < -edge_tolerance) return std::nullopt;
  if (unit.dot((r - q).cross(x - q)) < -edge_tolerance) return std::nullopt;
  if (unit.dot((p - r).cross(x - r)) < -edge_tolerance) return std::nullopt;
  return EdgeTriangleCrossing{s, x, unit};
}

}  // namespace weft
