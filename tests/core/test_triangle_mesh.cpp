// Vertex normals, surface area and rigid transforms (with the Euler rotation they use).
#include "core/triangle_mesh.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "core/mesh_generators.hpp"

namespace weft {
namespace {

TEST(VertexNormals, FlatGridPointsUp) {
  for (const auto triangulation :
       {GridTriangulation::regular, GridTriangulation::alternating, GridTriangulation::cross}) {
    const TriangleMesh grid = make_grid(6, 5, 2.0, 1.0, triangulation);
    const Positions normals = vertex_normals(grid.positions, grid.triangles);
    ASSERT_EQ(normals.cols(), grid.num_vertices());
    for (int v = 0; v < grid.num_vertices(); ++v) {
      EXPECT_TRUE(normals.col(v).isApprox(Vec3::UnitZ(), 1e-12)) << "vertex " << v;
    }
  }
}

TEST(VertexNormals, SpherePointsAwayFromCentre) {
  const TriangleMesh sphere = make_uv_sphere(2.0, 16, 9);
  const Positions normals = vertex_normals(sphere.positions, sphere.triangles);
  for (int v = 0; v < sphere.num_vertices(); ++v) {
    EXPECT_NEAR(normals.col(v).norm(), 1.0, 1e-12);
    EXPECT_GT(normals.col(v).dot(sphere.positions.col(v).normalized()), 0.99) << "vertex " << v;
  }
}

TEST(VertexNormals, WeightedByArea) {
  // Vertex 0 touches a triangle of area 1 facing +Z and one of area 1.5 facing +X.
  Positions positions(3, 5);
  positions << 0, 2, 0, 0, 0,  //
      0, 0, 1, 1, 0,           //
      0, 0, 0, 0, 3;
  Triangles triangles(3, 2);
  triangles << 0, 0,  //
      1, 3,           //
      2, 4;
  const Positions normals = vertex_normals(positions, triangles);
  EXPECT_TRUE(normals.col(0).isApprox(Vec3(1.5, 0.0, 1.0).normalized(), 1e-12));
  EXPECT_TRUE(normals.col(1).isApprox(Vec3::UnitZ(), 1e-12));
  EXPECT_TRUE(normals.col(4).isApprox(Vec3::UnitX(), 1e-12));
}

TEST(VertexNormals, ZeroWithoutArea) {
  // Vertex 3 touches nothing; triangle 1 is degenerate (collinear), so vertices 4 and 5 get zero.
  Positions positions(3, 6);
  positions << 0, 1, 0, 5, 0, 0,  //
      0, 0, 1, 5, 1, 2,           //
      0, 0, 0, 5, 0, 0;
  Triangles triangles(3, 2);
  triangles << 0, 0,  //
      1, 4,           //
      2, 5;
  const Positions normals = vertex_normals(positions, triangles);
  EXPECT_EQ(normals.col(3), Vec3::Zero());
  EXPECT_EQ(normals.col(4), Vec3::Zero());
  EXPECT_EQ(normals.col(5), Vec3::Zero());
  EXPECT_TRUE(normals.col(0).isApprox(Vec3::UnitZ()));
}

TEST(SurfaceArea, GridIsWidthTimesHeight) {
  for (const auto triangulation :
       {GridTriangulation::regular, GridTriangulation::alternating, GridTriangulation::cross}) {
    const TriangleMesh grid = make_grid(7, 4, 2.5, 1.5, triangulation);
    EXPECT_NEAR(surface_area(grid.positions, grid.triangles), 2.5 * 1.5, 1e-12);
  }
}

TEST(SurfaceArea, BoxAndSphere) {
  const TriangleMesh box = make_box(Vec3(0.5, 1.0, 2.0));
  EXPECT_NEAR(surface_area(box.positions, box.triangles), 2.0 * (1 * 2 + 1 * 4 + 2 * 4), 1e-12);
  const TriangleMesh sphere = make_uv_sphere(1.0, 128, 64);
  EXPECT_NEAR(surface_area(sphere.positions, sphere.triangles), 4.0 * pi, 2e-3 * 4.0 * pi);
  EXPECT_EQ(surface_area(box.positions, Triangles(3, 0)), 0.0);
}

TEST(RotationFromEulerDegrees, AppliesXThenYThenZ) {
  // About x by 90 takes +Y to +Z, then about y by 90 takes +Z to +X.
  EXPECT_TRUE((rotation_from_euler_degrees(Vec3(90, 90, 0)) * Vec3::UnitY()).isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_TRUE((rotation_from_euler_degrees(Vec3(0, 0, 90)) * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_TRUE(rotation_from_euler_degrees(Vec3::Zero()).isIdentity());

  const Vec3 degrees(30.0, -45.0, 120.0);
  const Vec3 radians = degrees * pi / 180.0;
  const Mat3 expected =
      (Eigen::AngleAxisd(radians.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(radians.y(), Vec3::UnitY()) *
       Eigen::AngleAxisd(radians.x(), Vec3::UnitX()))
          .toRotationMatrix();
  const Mat3 rotation = rotation_from_euler_degrees(degrees);
  EXPECT_TRUE(rotation.isApprox(expected, 1e-14));
  EXPECT_TRUE((rotation.transpose() * rotation).isIdentity(1e-14));
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-14);
}

TEST(TransformPositions, ScalesRotatesThenTranslates) {
  Positions positions(3, 2);
  positions << 1, 0,  //
      0, 0,           //
      0, 2;
  transform_positions(positions, rotation_from_euler_degrees(Vec3(0, 0, 90)), 2.0, Vec3(1, 2, 3));
  EXPECT_TRUE(positions.col(0).isApprox(Vec3(1, 4, 3), 1e-12));
  EXPECT_TRUE(positions.col(1).isApprox(Vec3(1, 2, 7), 1e-12));
}

TEST(TransformPositions, PreservesShape) {
  TriangleMesh grid = make_grid(5, 5, 1.0, 2.0, GridTriangulation::alternating);
  transform_positions(grid.positions, rotation_from_euler_degrees(Vec3(10, 20, 30)), 3.0, Vec3(-1, 0, 5));
  EXPECT_NEAR(surface_area(grid.positions, grid.triangles), 9.0 * 2.0, 1e-12);
}

}  // namespace
}  // namespace weft
