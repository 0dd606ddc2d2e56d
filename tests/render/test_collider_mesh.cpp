#include "render/collider_mesh.hpp"

#include <gtest/gtest.h>

#include "render/world_view.hpp"

namespace weft {
namespace {

Positions placed_positions(const TriangleMesh& mesh, const Eigen::Isometry3d& placement) {
  Positions placed(3, mesh.num_vertices());
  for (int i = 0; i < mesh.num_vertices(); ++i) placed.col(i) = placement * Vec3(mesh.positions.col(i));
  return placed;
}

TEST(ColliderMesh, PlaneSquareLiesOnThePlaneFacingItsNormal) {
  Collider plane;
  plane.shape = ColliderShape::plane;
  plane.center = Vec3(0.0, -0.6, 0.0);
  plane.normal = Vec3(0.0, 1.0, 1.0).normalized();
  const TriangleMesh mesh = collider_mesh(plane, 5.0);
  const Eigen::Isometry3d placement = collider_placement(plane, Vec3(1.0, 2.0, 3.0));
  const Positions placed = placed_positions(mesh, placement);
  const Positions normals = vertex_normals(placed, mesh.triangles);
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    Vec3 outward;
    EXPECT_NEAR(signed_distance(plane, placed.col(i), outward), 0.0, 1e-9);
    EXPECT_TRUE(normals.col(i).isApprox(plane.normal, 1e-9));
  }
  // Centred on the anchor's foot on the plane.
  Vec3 outward;
  EXPECT_NEAR(signed_distance(plane, placement.translation(), outward), 0.0, 1e-9);
  EXPECT_NEAR((placed.rowwise().mean() - placement.translation()).norm(), 0.0, 1e-9);
}

TEST(ColliderMesh, BoxFacesShadeFlat) {
  Collider box;
  box.shape = ColliderShape::box;
  box.half_extents = Vec3(0.3, 0.2, 0.1);
  const TriangleMesh mesh = collider_mesh(box, 5.0);
  EXPECT_EQ(mesh.num_vertices(), 3 * mesh.num_triangles());
  const Positions normals = vertex_normals(mesh.positions, mesh.triangles);
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    // Each vertex normal is a face normal: one axis, pointing out of the box.
    EXPECT_NEAR(normals.col(i).cwiseAbs().maxCoeff(), 1.0, 1e-9);
    EXPECT_GT(normals.col(i).dot(mesh.positions.col(i)), 0.0);
  }
}

TEST(ColliderMesh, SphereVerticesAreOnTheSurface) {
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = Vec3(1.0, 2.0, 3.0);
  sphere.radius = 0.7;
  const TriangleMesh mesh = collider_mesh(sphere, 5.0);
  const Positions placed = placed_positions(mesh, collider_placement(sphere, Vec3::Zero()));
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    EXPECT_NEAR((placed.col(i) - sphere.center).norm(), sphere.radius, 1e-9);
  }
}

TEST(WorldBounds, CoverClothsSolidsAndTheFloorBelow) {
  World world;
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = Vec3(0.0, 1.0, 0.0);
  sphere.radius = 0.5;
  world.add_collider(sphere);
  Collider floor;
  floor.shape = ColliderShape::plane;
  floor.center = Vec3(0.0, -2.0, 0.0);
  world.add_collider(floor);
  const Eigen::AlignedBox3d bounds = world_bounds(world);
  EXPECT_TRUE(bounds.min().isApprox(Vec3(-0.5, -2.0, -0.5)));
  EXPECT_TRUE(bounds.max().isApprox(Vec3(0.5, 1.5, 0.5)));
}

}  // namespace
}  // namespace weft
