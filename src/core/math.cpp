#include "core/math.hpp"

#include <Eigen/Geometry>

namespace weft {

Mat3 rotation_from_euler_degrees(const Vec3& degrees) {
  const Vec3 radians = degrees * (pi / 180.0);
  const Eigen::AngleAxisd about_x(radians.x(), Vec3::UnitX());
  const Eigen::AngleAxisd about_y(radians.y(), Vec3::UnitY());
  const Eigen::AngleAxisd about_z(radians.z(), Vec3::UnitZ());
  return (about_z * about_y * about_x).toRotationMatrix();
}

}  // namespace weft
