#include "collision/collider.hpp"

#include <cmath>

namespace weft {

namespace {

double box_signed_distance(const Vec3& center, const Vec3& half_extents, const Vec3& p, Vec3& normal) {
  const Vec3 local = p - center;
  const Vec3 q = local.cwiseAbs() - half_extents;
  if ((q.array() > 0.0).any()) {
    // Outside: distance to the closest point of the box.
    const Vec3 closest = local.cwiseMax(-half_extents).cwiseMin(half_extents);
    const Vec3 offset = local - closest;
    const double distance = offset.norm();
    normal = offset / distance;
    return distance;
  }
  // Inside: the nearest face decides.
  Eigen::Index axis = 0;
  const double distance = q.maxCoeff(&axis);
  normal = Vec3::Zero();
  normal[axis] = local[axis] >= 0.0 ? 1.0 : -1.0;
  return distance;
}

}  // namespace

double signed_distance(const Collider& collider, const Vec3& p, Vec3& outward_normal) {
  switch (collider.shape) {
    case ColliderShape::plane:
      outward_normal = collider.normal;
      return collider.normal.dot(p - collider.center);
    case ColliderShape::sphere: {
      const Vec3 offset = p - collider.center;
      const double length = offset.norm();
      outward_normal = length > 0.0 ? Vec3(offset / length) : Vec3::UnitY();
      return length - collider.radius;
    }
    case ColliderShape::box:
      return box_signed_distance(collider.center, collider.half_extents, p, outward_normal);
  }
  outward_normal = Vec3::UnitY();
  return 0.0;
}

const char* to_string(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::plane:
      return "plane";
    case ColliderShape::sphere:
      return "sphere";
    case ColliderShape::box:
      return "box";
  }
  return "unknown";
}

}  // namespace weft
