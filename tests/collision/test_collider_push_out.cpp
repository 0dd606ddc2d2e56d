// push_out_of_collider: cloth vertices inside a collider end `margin` outside the triangles that
// stand for it, along its normal; pinned ones are counted and stay; the outside is left alone.
#include "collision/collider_push_out.hpp"

#include <gtest/gtest.h>

#include "collision/collider_geometry.hpp"
#include "collision/edge_triangle_crossing.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

// Whether p is inside the closed triangle mesh: a ray from it crosses it an odd number of times.
bool inside_mesh(const Vec3& p, const TriangleMesh& mesh) {
  const Vec3 far = p + Vec3(10.0, 3.7, 1.3);  // a direction no facet edge of these meshes lies along
  int crossings = 0;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    crossings += edge_triangle_crossing(p, far, mesh.positions.col(mesh.triangles(0, t)),
                                        mesh.positions.col(mesh.triangles(1, t)),
                                        mesh.positions.col(mesh.triangles(2, t)))
                     .has_value();
  }
  return crossings % 2 == 1;
}

TEST(ColliderPushOut, VerticesInsideASphereEndOutsideItsFacets) {
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.radius = 0.5;
  const TriangleMesh surface = collider_surface(sphere);
  // Deep inside, just inside the solid, between the solid and its circumscribed facets, outside.
  Positions x(3, 4);
  x.col(0) = Vec3(0.1, 0.3, 0.0);
  x.col(1) = Vec3(0.0, 0.499, 0.0);
  x.col(2) = Vec3(0.3, 0.3, 0.3).normalized() * 0.5005;
  x.col(3) = Vec3(0.0, 0.6, 0.0);
  ASSERT_TRUE(inside_mesh(x.col(2), surface)) << "vertex 2 should lie between the solid and its facets";
  Positions push = Positions::Zero(3, 4);
  const double margin = 1e-3;
  const ColliderPushOut result =
      push_out_of_collider(sphere, 0.0, surface.positions, surface.triangles, x, Triangles(3, 0),
                           Eigen::VectorXd::Ones(4), margin, push);
  EXPECT_EQ(result.moved, 3);
  EXPECT_EQ(result.pinned_inside, 0);
  EXPECT_TRUE(push.col(3).isZero(0.0));
  for (int v = 0; v < 3; ++v) {
    const Vec3 moved = x.col(v) + push.col(v);
    EXPECT_FALSE(inside_mesh(moved, surface)) << "vertex " << v;
    EXPECT_TRUE(push.col(v).normalized().isApprox(x.col(v).normalized(), 1e-12)) << "along the normal";
    EXPECT_LT(moved.norm(), 0.5 * 1.02 + margin) << "no farther than the facets and the margin";
  }
}

TEST(ColliderPushOut, AMovingBoxPushesAlongItsNearestFace) {
  Collider box;
  box.shape = ColliderShape::box;
  box.half_extents = Vec3(0.5, 0.1, 0.5);
  box.motion.velocity = Vec3(1.0, 0.0, 0.0);  // at t = 1 the box is centred at x = 1
  const TriangleMesh rest = collider_surface(box);
  Positions surface(3, rest.num_vertices());
  box.motion.place(rest.positions, 1.0, surface);
  Positions x(3, 1);
  x.col(0) = Vec3(1.2, 0.07, 0.0);  // 3 cm below the top face
  Positions push = Positions::Zero(3, 1);
  const ColliderPushOut result = push_out_of_collider(box, 1.0, surface, rest.triangles, x, Triangles(3, 0),
                                                      Eigen::VectorXd::Ones(1), 1e-3, push);
  EXPECT_EQ(result.moved, 1);
  EXPECT_TRUE((x.col(0) + push.col(0)).isApprox(Vec3(1.2, 0.101, 0.0), 1e-12));
}

TEST(ColliderPushOut, ASheetDeepInABoxComesOutThroughTheFaceItEnteredInOnePiece) {
  // A vertical sheet entering a box through its top (y = 0.2) 5 cm from its +z side, 30 cm deep:
  // its deep vertices are nearer the side face than the top, yet all leave through the top.
  Collider box;
  box.shape = ColliderShape::box;
  box.half_extents = Vec3(0.5, 0.2, 0.5);
  const TriangleMesh surface = collider_surface(box);
  const TriangleMesh sheet = make_grid(11, 11, 0.4, 0.4, GridTriangulation::alternating);
  Positions x = sheet.positions;
  x.colwise() += Vec3(0.0, 0.1, 0.45);  // y in [-0.1, 0.3], the plane z = 0.45
  Positions push = Positions::Zero(3, x.cols());
  const ColliderPushOut result =
      push_out_of_collider(box, 0.0, surface.positions, surface.triangles, x, sheet.triangles,
                           Eigen::VectorXd::Ones(x.cols()), 1e-3, push);
  int inside = 0;
  for (Eigen::Index v = 0; v < x.cols(); ++v) inside += x(1, v) < 0.2;
  EXPECT_EQ(result.moved, inside);
  for (Eigen::Index v = 0; v < x.cols(); ++v) {
    if (x(1, v) >= 0.2) {
      EXPECT_TRUE(push.col(v).isZero(0.0)) << "vertex " << v << " is outside";
      continue;
    }
    EXPECT_NEAR(push(0, v), 0.0, 1e-12) << "vertex " << v;
    EXPECT_NEAR(push(2, v), 0.0, 1e-12) << "vertex " << v;
    EXPECT_NEAR(x(1, v) + push(1, v), 0.201, 1e-9) << "vertex " << v << " ends just above the top";
  }
}

TEST(ColliderPushOut, APinnedVertexInsideIsCountedAndStays) {
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  const TriangleMesh surface = collider_surface(sphere);
  Positions x(3, 2);
  x.col(0) = Vec3(0.0, 0.4, 0.0);
  x.col(1) = Vec3(0.0, 0.45, 0.0);
  Eigen::VectorXd inverse_mass(2);
  inverse_mass << 1.0, 0.0;
  Positions push = Positions::Zero(3, 2);
  const ColliderPushOut result = push_out_of_collider(sphere, 0.0, surface.positions, surface.triangles, x,
                                                      Triangles(3, 0), inverse_mass, 1e-3, push);
  EXPECT_EQ(result.moved, 1);
  EXPECT_EQ(result.pinned_inside, 1);
  EXPECT_EQ(result.first_pinned, 1);
  EXPECT_TRUE(push.col(1).isZero(0.0));
}

TEST(ColliderPushOut, MeshesAndOpenCylindersHaveNoInside) {
  Collider tube;
  tube.shape = ColliderShape::cylinder;
  tube.capped = false;
  EXPECT_FALSE(collider_has_inside(tube));
  tube.capped = true;
  EXPECT_TRUE(collider_has_inside(tube));
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  EXPECT_FALSE(collider_has_inside(mesh));
}

}  // namespace
}  // namespace weft
