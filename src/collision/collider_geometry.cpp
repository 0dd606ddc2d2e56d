#include "collision/collider_geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "core/mesh_generators.hpp"

namespace weft {

namespace {

// Rotation taking +Y (the generators' axis) to `axis`.
Mat3 rotation_from_y(const Vec3& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitY(), axis.normalized()).toRotationMatrix();
}

// Smallest margin, over the faces, between a face's plane and the solid's support in the
// direction of the face's outward normal: >= 0 when every face plane clears the solid.
double smallest_face_margin(const TriangleMesh& mesh, const std::function<double(const Vec3&)>& support) {
  double margin = HUGE_VAL;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a = mesh.positions.col(mesh.triangles(0, t));
    const Vec3 b = mesh.positions.col(mesh.triangles(1, t));
    const Vec3 c = mesh.positions.col(mesh.triangles(2, t));
    const Vec3 n = (b - a).cross(c - a).normalized();
    margin = std::min(margin, n.dot(a) - support(n));
  }
  return margin;
}

// A UV sphere of unit radius around the origin whose hemispheres are pulled apart along Y by
// +-half_length (an odd number of stacks leaves a band of quads between them: the capsule's
// side), then scaled away from the segment until every face plane clears the capsule.
TriangleMesh circumscribed_capsule(double radius, double half_length, int slices, int stacks) {
  TriangleMesh mesh = make_uv_sphere(1.0, slices, stacks);
  Positions offsets = mesh.positions;  // from the nearest point of the segment, unit scale
  Eigen::VectorXd along(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) along[v] = mesh.positions(1, v) > 0.0 ? half_length : -half_length;
  const auto support = [&](const Vec3& n) { return std::abs(n.y()) * half_length + radius; };
  double scale = radius;
  for (int iteration = 0; iteration < 8; ++iteration) {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      mesh.positions.col(v) = scale * offsets.col(v) + Vec3(0.0, along[v], 0.0);
    }
    const double margin = smallest_face_margin(mesh, support);
    if (margin >= 0.0) break;
    // Face planes move out about linearly with the scale; a little extra ends the loop.
    scale *= (radius - margin) / radius * (1.0 + 1e-9);
  }
  return mesh;
}

}  // namespace

TriangleMesh collider_surface(const Collider& collider, const ColliderTessellation& tessellation) {
  TriangleMesh mesh;
  Mat3 rotation = Mat3::Identity();
  switch (collider.shape) {
    case ColliderShape::plane: {
      const double s = collider.plane_half_size;
      mesh = make_grid(2, 2, 2.0 * s, 2.0 * s, GridTriangulation::regular);
      rotation = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), collider.normal).toRotationMatrix();
      break;
    }
    case ColliderShape::sphere:
      mesh = circumscribed_capsule(collider.radius, 0.0, tessellation.sphere_slices, tessellation.sphere_stacks);
      break;
    case ColliderShape::box:
      mesh = make_box(collider.half_extents);
      break;
    case ColliderShape::capsule:
      mesh = circumscribed_capsule(collider.radius, collider.half_length, tessellation.sphere_slices,
                                   tessellation.sphere_stacks | 1);
      rotation = rotation_from_y(collider.axis);
      break;
    case ColliderShape::cylinder:
      mesh = make_cylinder(collider.radius, 2.0 * collider.half_length, tessellation.cylinder_segments,
                           collider.capped);
      rotation = rotation_from_y(collider.axis);
      break;
    case ColliderShape::mesh:
      if (collider.mesh.num_triangles() == 0) {
        throw std::invalid_argument("collider \"" + collider.name + "\": the mesh has no triangles");
      }
      return collider.mesh;
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    mesh.positions.col(v) = rotation * mesh.positions.col(v) + collider.center;
  }
  return mesh;
}

}  // namespace weft
