#include "collision/collider.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

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

// Distance to a segment minus the radius.
double capsule_signed_distance(const Collider& c, const Vec3& p, Vec3& normal) {
  const Vec3 local = p - c.center;
  const double along = std::clamp(local.dot(c.axis), -c.half_length, c.half_length);
  const Vec3 offset = local - along * c.axis;
  const double length = offset.norm();
  normal = length > 0.0 ? Vec3(offset / length) : Vec3(c.axis.unitOrthogonal());
  return length - c.radius;
}

// Solid finite cylinder: the radial and axial distances combined as for a 2D box.
double cylinder_signed_distance(const Collider& c, const Vec3& p, Vec3& normal) {
  const Vec3 local = p - c.center;
  const double along = local.dot(c.axis);
  const Vec3 radial = local - along * c.axis;
  const double r = radial.norm();
  const Vec3 radial_dir = r > 0.0 ? Vec3(radial / r) : Vec3(c.axis.unitOrthogonal());
  const double dr = r - c.radius;
  const double da = std::abs(along) - c.half_length;
  const Vec3 axial_dir = along >= 0.0 ? c.axis : Vec3(-c.axis);
  if (dr > 0.0 && da > 0.0) {
    const double distance = std::hypot(dr, da);
    normal = (dr * radial_dir + da * axial_dir) / distance;
    return distance;
  }
  normal = dr > da ? radial_dir : axial_dir;
  return std::max(dr, da);
}

}  // namespace

Mat3 ColliderMotion::rotation(double t) const {
  if (angular_velocity == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(angular_velocity * t, axis).toRotationMatrix();
}

Vec3 ColliderMotion::translation(double t) const { return pivot - rotation(t) * pivot + velocity * t; }

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
    case ColliderShape::capsule:
      return capsule_signed_distance(collider, p, outward_normal);
    case ColliderShape::cylinder:
      return cylinder_signed_distance(collider, p, outward_normal);
    case ColliderShape::mesh:
      break;
  }
  outward_normal = Vec3::UnitY();
  return std::numeric_limits<double>::infinity();
}

double signed_distance_at(const Collider& collider, const Vec3& p, double t) {
  const Vec3 rest = collider.motion.rotation(t).transpose() * (p - collider.motion.translation(t));
  Vec3 normal;
  return signed_distance(collider, rest, normal);
}

const char* to_string(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::plane:
      return "plane";
    case ColliderShape::sphere:
      return "sphere";
    case ColliderShape::box:
      return "box";
    case ColliderShape::capsule:
      return "capsule";
    case ColliderShape::cylinder:
      return "cylinder";
    case ColliderShape::mesh:
      return "mesh";
  }
  return "unknown";
}

}  // namespace weft
