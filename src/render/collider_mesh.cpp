#include "render/collider_mesh.hpp"

#include "collision/collider_geometry.hpp"
#include "core/mesh_generators.hpp"

namespace weft {

namespace {

constexpr int sphere_slices = 48;
constexpr int sphere_stacks = 24;

}  // namespace

TriangleMesh collider_mesh(const Collider& collider, double plane_half_size) {
  switch (collider.shape) {
    case ColliderShape::sphere:
      return make_uv_sphere(collider.radius, sphere_slices, sphere_stacks);
    case ColliderShape::box:
      return split_vertices(make_box(collider.half_extents));
    case ColliderShape::plane:
      return make_grid(2, 2, 2.0 * plane_half_size, 2.0 * plane_half_size, GridTriangulation::regular);
    case ColliderShape::capsule:
    case ColliderShape::cylinder:
    case ColliderShape::mesh: {
      // The collision pipeline's own surface, moved into the collider's frame.
      TriangleMesh mesh = collider_surface(collider);
      mesh.positions.colwise() -= collider.center;
      return split_vertices(mesh);
    }
  }
  return {};
}

Eigen::Isometry3d collider_placement(const Collider& collider, const Vec3& plane_anchor, double time) {
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  if (collider.shape != ColliderShape::plane) {
    // Scripted motion about the pivot, applied after the shape's own placement.
    const Mat3 rotation = collider.motion.rotation(time);
    placement.linear() = rotation;
    placement.translation() = rotation * collider.center + collider.motion.translation(time);
    return placement;
  }
  const Vec3 normal = collider.normal.normalized();
  placement.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), normal).toRotationMatrix();
  placement.translation() = plane_anchor - normal.dot(plane_anchor - collider.center) * normal;
  return placement;
}

TriangleMesh split_vertices(const TriangleMesh& mesh) {
  TriangleMesh split;
  const int corners = 3 * mesh.num_triangles();
  split.positions.resize(3, corners);
  split.triangles.resize(3, mesh.num_triangles());
  if (mesh.has_uvs()) split.uvs.resize(2, corners);
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int corner = 3 * t + k;
      split.positions.col(corner) = mesh.positions.col(mesh.triangles(k, t));
      if (mesh.has_uvs()) split.uvs.col(corner) = mesh.uvs.col(mesh.triangles(k, t));
      split.triangles(k, t) = corner;
    }
  }
  return split;
}

}  // namespace weft
