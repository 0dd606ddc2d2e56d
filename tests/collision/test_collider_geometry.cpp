// Collider surfaces: tessellations that contain their analytic solid (every face plane clears
// it) and stay close to it, closed where the shape is closed; signed distances and the scripted
// motion.
#include "collision/collider_geometry.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "core/topology.hpp"

namespace weft {
namespace {

// Largest distance by which the solid pokes through a face plane (<= 0: contained), from the
// support function of a capsule (a sphere when half_length is 0): max over the segment of n.x,
// plus the radius; and the largest distance of a mesh vertex from the surface.
struct Fit {
  double poke = -HUGE_VAL;
  double farthest_vertex = 0.0;
};

Fit fit_of(const Collider& collider, const TriangleMesh& mesh) {
  const double half_length = collider.shape == ColliderShape::capsule ? collider.half_length : 0.0;
  const Vec3 p = collider.center + half_length * collider.axis;
  const Vec3 q = collider.center - half_length * collider.axis;
  Fit fit;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a = mesh.positions.col(mesh.triangles(0, t));
    const Vec3 b = mesh.positions.col(mesh.triangles(1, t));
    const Vec3 c = mesh.positions.col(mesh.triangles(2, t));
    const Vec3 n = (b - a).cross(c - a).normalized();
    fit.poke = std::max(fit.poke, std::max(n.dot(p), n.dot(q)) + collider.radius - n.dot(a));
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    Vec3 normal;
    fit.farthest_vertex = std::max(fit.farthest_vertex, signed_distance(collider, mesh.positions.col(v), normal));
  }
  return fit;
}

TEST(ColliderGeometry, SphereAndCapsuleSurfacesContainTheirSolid) {
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = Vec3(0.3, -0.2, 1.0);
  sphere.radius = 0.5;
  const TriangleMesh sphere_mesh = collider_surface(sphere);
  const Fit sphere_fit = fit_of(sphere, sphere_mesh);
  EXPECT_LE(sphere_fit.poke, 1e-12);
  EXPECT_LT(sphere_fit.farthest_vertex, 0.01 * sphere.radius);
  EXPECT_TRUE(build_topology(sphere_mesh.triangles, sphere_mesh.num_vertices()).boundary_edges.empty());

  Collider capsule;
  capsule.shape = ColliderShape::capsule;
  capsule.center = Vec3(1, 2, 3);
  capsule.axis = Vec3(1, 1, 0).normalized();
  capsule.radius = 0.2;
  capsule.half_length = 0.6;
  const TriangleMesh capsule_mesh = collider_surface(capsule);
  const Fit capsule_fit = fit_of(capsule, capsule_mesh);
  EXPECT_LE(capsule_fit.poke, 1e-12);
  EXPECT_LT(capsule_fit.farthest_vertex, 0.05 * capsule.radius);
  EXPECT_TRUE(build_topology(capsule_mesh.triangles, capsule_mesh.num_vertices()).boundary_edges.empty());
}

TEST(ColliderGeometry, BoxPlaneAndCylinderSurfaces) {
  Collider box;
  box.shape = ColliderShape::box;
  box.center = Vec3(1, 0, 0);
  box.half_extents = Vec3(0.1, 0.2, 0.3);
  const TriangleMesh box_mesh = collider_surface(box);
  EXPECT_EQ(box_mesh.num_triangles(), 12);
  for (int v = 0; v < box_mesh.num_vertices(); ++v) {
    EXPECT_TRUE((box_mesh.positions.col(v) - box.center).cwiseAbs().isApprox(box.half_extents, 1e-14));
  }

  Collider plane;
  plane.center = Vec3(0, -1, 0);
  plane.normal = Vec3(0, 0, 1);
  plane.plane_half_size = 3.0;
  const TriangleMesh plane_mesh = collider_surface(plane);
  ASSERT_EQ(plane_mesh.num_triangles(), 2);
  for (int v = 0; v < plane_mesh.num_vertices(); ++v) EXPECT_NEAR(plane_mesh.positions(2, v), 0.0, 1e-15);
  const Vec3 front = (plane_mesh.positions.col(plane_mesh.triangles(1, 0)) - plane_mesh.positions.col(plane_mesh.triangles(0, 0)))
                         .cross(plane_mesh.positions.col(plane_mesh.triangles(2, 0)) -
                                plane_mesh.positions.col(plane_mesh.triangles(0, 0)));
  EXPECT_GT(front.z(), 0.0) << "the square faces along the normal";

  Collider drum;
  drum.shape = ColliderShape::cylinder;
  drum.axis = Vec3::UnitZ();
  drum.radius = 0.6;
  drum.half_length = 0.5;
  for (bool capped : {true, false}) {
    drum.capped = capped;
    const TriangleMesh mesh = collider_surface(drum);
    const MeshTopology topology = build_topology(mesh.triangles, mesh.num_vertices());
    EXPECT_EQ(topology.boundary_edges.empty(), capped);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      EXPECT_LE(std::abs(mesh.positions(2, v)), 0.5 + 1e-12);
      EXPECT_LE(mesh.positions.col(v).head<2>().norm(), 0.6 + 1e-12);
    }
  }

  Collider empty;
  empty.shape = ColliderShape::mesh;
  EXPECT_THROW(collider_surface(empty), std::invalid_argument);
}

TEST(ColliderGeometry, SignedDistancesFollowTheScriptedMotion) {
  Collider drum;
  drum.shape = ColliderShape::cylinder;
  drum.axis = Vec3::UnitZ();
  drum.radius = 1.0;
  drum.half_length = 1.0;
  drum.center = Vec3(2, 0, 0);
  drum.motion.pivot = Vec3::Zero();
  drum.motion.axis = Vec3::UnitZ();
  drum.motion.angular_velocity = pi / 2;  // a quarter turn per second about the z axis
  drum.motion.velocity = Vec3(0, 0, 1);
  // At t = 1 the centre is at R(90 deg) (2, 0, 0) + (0, 0, 1) = (0, 2, 1).
  EXPECT_NEAR(signed_distance_at(drum, Vec3(0, 2, 1), 1.0), -1.0, 1e-12);
  EXPECT_NEAR(signed_distance_at(drum, Vec3(0, 2, 2.5), 1.0), 0.5, 1e-12);
  EXPECT_NEAR(signed_distance_at(drum, Vec3(2, 0, 0), 0.0), -1.0, 1e-12);
  EXPECT_GT(signed_distance_at(drum, Vec3(2, 0, 0), 1.0), 0.0);
  const Mat3 rotation = drum.motion.rotation(1.0);
  EXPECT_TRUE((rotation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_TRUE(drum.motion.translation(0.0).isZero(1e-15));

  Collider capsule;
  capsule.shape = ColliderShape::capsule;
  capsule.axis = Vec3::UnitX();
  capsule.radius = 0.5;
  capsule.half_length = 1.0;
  Vec3 normal;
  EXPECT_NEAR(signed_distance(capsule, Vec3(0.5, 1.0, 0), normal), 0.5, 1e-15);
  EXPECT_TRUE(normal.isApprox(Vec3::UnitY()));
  EXPECT_NEAR(signed_distance(capsule, Vec3(2.0, 0, 0), normal), 0.5, 1e-15);
  EXPECT_TRUE(normal.isApprox(Vec3::UnitX()));
}

}  // namespace
}  // namespace weft
