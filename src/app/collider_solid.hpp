#pragma once
// A collider's analytic solid for the exact checks (check/solid_distance.hpp), placed where the
// collider's motion carries it: header-only, so that tests and benchmarks that judge a World
// read colliders the way the program does.
#include <optional>

#include "check/solid_distance.hpp"
#include "collision/collider.hpp"

namespace weft {

// The collider's solid placed by `rotation` and `translation` (a point x of the collider at
// time 0 is at rotation * x + translation), or nothing for a shape without an inside (a mesh,
// an open cylinder).
inline std::optional<AnalyticSolid> collider_solid(const Collider& collider, const Mat3& rotation,
                                                   const Vec3& translation) {
  AnalyticSolid solid;
  switch (collider.shape) {
    case ColliderShape::plane:
      solid.kind = SolidKind::half_space;
      break;
    case ColliderShape::sphere:
      solid.kind = SolidKind::sphere;
      break;
    case ColliderShape::box:
      solid.kind = SolidKind::box;
      break;
    case ColliderShape::capsule:
      solid.kind = SolidKind::capsule;
      break;
    case ColliderShape::cylinder:
      if (!collider.capped) return std::nullopt;
      solid.kind = SolidKind::capped_cylinder;
      break;
    case ColliderShape::mesh:
      return std::nullopt;
  }
  solid.normal = collider.normal;
  solid.radius = collider.radius;
  solid.half_extents = collider.half_extents;
  solid.axis = collider.axis;
  solid.half_length = collider.half_length;
  solid.orientation = rotation;
  solid.center = rotation * collider.center + translation;
  return solid;
}

// The same at time t of the collider's scripted motion.
inline std::optional<AnalyticSolid> collider_solid_at(const Collider& collider, double t) {
  return collider_solid(collider, collider.motion.rotation(t), collider.motion.translation(t));
}

}  // namespace weft
