#include "check/solid_distance.hpp"

#include <algorithm>
#include <cmath>

namespace weft {

double reference_signed_distance(const AnalyticSolid& solid, const Vec3& p) {
  const Vec3 local = solid.orientation.transpose() * (p - solid.center);
  switch (solid.kind) {
    case SolidKind::half_space:
      return solid.normal.normalized().dot(local);
    case SolidKind::sphere:
      return local.norm() - solid.radius;
    case SolidKind::box: {
      // Outside: distance to the nearest point of the box; inside: minus the distance to the
      // nearest face.
      const Vec3 q = local.cwiseAbs() - solid.half_extents;
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
    case SolidKind::capsule: {
      // Distance to the axis segment, less the radius.
      const Vec3 axis = solid.axis.normalized();
      const double along = std::clamp(local.dot(axis), -solid.half_length, solid.half_length);
      return (local - along * axis).norm() - solid.radius;
    }
    case SolidKind::capped_cylinder: {
      // The box formula in (distance from the axis, distance along it).
      const Vec3 axis = solid.axis.normalized();
      const double along = local.dot(axis);
      const Vec2 q((local - along * axis).norm() - solid.radius, std::abs(along) - solid.half_length);
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
  }
  return HUGE_VAL;
}

}  // namespace weft
