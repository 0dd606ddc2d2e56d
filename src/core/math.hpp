#pragma once
// Math vocabulary over Eigen. Per-vertex data is stored as 3 x N column-major matrices, so
// the coordinates of one vertex are contiguous and x.col(i) is that vertex's position.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace weft {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec3i = Eigen::Vector3i;

// Per-element stacks of vertex coordinates: 2 vertices (springs), 3 (triangles), 4 (hinges).
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

using Positions = Eigen::Matrix3Xd;  // one column per vertex (3 x n_vertices)
using Triangles = Eigen::Matrix3Xi;  // vertex indices, counter-clockwise from the front (3 x n_triangles)

inline constexpr double pi = 3.14159265358979323846;

// The cross-product matrix: cross_matrix(a) * b = a x b.
inline Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

// Rotation from Euler angles in degrees, applied about x, then y, then z (R = Rz * Ry * Rx).
Mat3 rotation_from_euler_degrees(const Vec3& degrees);

}  // namespace weft
