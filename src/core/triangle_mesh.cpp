#include "core/triangle_mesh.hpp"

#include <Eigen/Geometry>

namespace weft {

Positions vertex_normals(const Positions& positions, const Triangles& triangles) {
  // The cross product of two sides is twice the triangle's area times its unit normal, so summing
  // it at the corners weights each triangle by its area.
  Positions normals = Positions::Zero(3, positions.cols());
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Vec3i tri = triangles.col(t);
    const Vec3 x0 = positions.col(tri[0]);
    const Vec3 area_normal = (positions.col(tri[1]) - x0).cross(positions.col(tri[2]) - x0);
    for (int k = 0; k < 3; ++k) normals.col(tri[k]) += area_normal;
  }
  for (Eigen::Index i = 0; i < normals.cols(); ++i) {
    const double length = normals.col(i).norm();
    if (length > 0.0) normals.col(i) /= length;
  }
  return normals;
}

double surface_area(const Positions& positions, const Triangles& triangles) {
  double area = 0.0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Vec3 x0 = positions.col(triangles(0, t));
    area += 0.5 * (positions.col(triangles(1, t)) - x0).cross(positions.col(triangles(2, t)) - x0).norm();
  }
  return area;
}

void transform_positions(Positions& positions, const Mat3& rotation, double scale, const Vec3& translation) {
  positions = (scale * rotation) * positions;
  positions.colwise() += translation;
}

}  // namespace weft
