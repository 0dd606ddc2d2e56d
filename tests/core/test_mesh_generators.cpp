// Procedural meshes: grid layout as documented, winding (front +Z, solids outward), volumes,
// and argument checks.
#include "core/mesh_generators.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "core/topology.hpp"

namespace weft {
namespace {

const GridTriangulation all_triangulations[] = {GridTriangulation::regular, GridTriangulation::alternating,
                                                GridTriangulation::cross};

Vec3 area_normal(const TriangleMesh& mesh, int t) {
  const Vec3 x0 = mesh.positions.col(mesh.triangles(0, t));
  return (mesh.positions.col(mesh.triangles(1, t)) - x0).cross(mesh.positions.col(mesh.triangles(2, t)) - x0);
}

// Volume enclosed by a closed mesh, positive when it faces outward (divergence theorem).
double signed_volume(const TriangleMesh& mesh) {
  double volume = 0.0;
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    volume += mesh.positions.col(mesh.triangles(0, t))
                  .dot(Vec3(mesh.positions.col(mesh.triangles(1, t)))
                           .cross(Vec3(mesh.positions.col(mesh.triangles(2, t))))) /
              6.0;
  }
  return volume;
}

// For a convex solid around the origin, every triangle faces away from the origin.
void expect_every_triangle_outward(const TriangleMesh& mesh) {
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 centroid =
        (mesh.positions.col(mesh.triangles(0, t)) + mesh.positions.col(mesh.triangles(1, t)) +
         mesh.positions.col(mesh.triangles(2, t))) /
        3.0;
    EXPECT_GT(area_normal(mesh, t).dot(centroid), 0.0) << "triangle " << t;
  }
}

template <typename Function>
void expect_invalid_argument(Function make, const std::string& words) {
  try {
    make();
    FAIL() << "expected std::invalid_argument mentioning " << words;
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

TEST(MakeGrid, LatticeLayoutAndUvs) {
  const int nx = 4, ny = 3;
  const double width = 3.0, height = 1.0;
  for (const auto triangulation : all_triangulations) {
    const TriangleMesh grid = make_grid(nx, ny, width, height, triangulation);
    ASSERT_TRUE(grid.has_uvs());
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const int v = j * nx + i;
        EXPECT_TRUE(grid.positions.col(v).isApprox(Vec3(-1.5 + i * 1.0, -0.5 + j * 0.5, 0.0)));
        EXPECT_TRUE(grid.uvs.col(v).isApprox(Vec2(i / 3.0, j / 2.0)));
      }
    }
  }
  EXPECT_EQ(make_grid(nx, ny, width, height, GridTriangulation::regular).num_vertices(), nx * ny);
  EXPECT_EQ(make_grid(nx, ny, width, height, GridTriangulation::regular).num_triangles(), 2 * 3 * 2);
  EXPECT_EQ(make_grid(nx, ny, width, height, GridTriangulation::alternating).num_triangles(), 2 * 3 * 2);
}

TEST(MakeGrid, CrossAddsQuadCentres) {
  const int nx = 4, ny = 3;
  const TriangleMesh grid = make_grid(nx, ny, 3.0, 1.0, GridTriangulation::cross);
  ASSERT_EQ(grid.num_vertices(), nx * ny + (nx - 1) * (ny - 1));
  ASSERT_EQ(grid.num_triangles(), 4 * (nx - 1) * (ny - 1));
  for (int j = 0; j < ny - 1; ++j) {
    for (int i = 0; i < nx - 1; ++i) {
      const int centre = nx * ny + j * (nx - 1) + i;
      const Vec3 expected =
          0.25 * (grid.positions.col(j * nx + i) + grid.positions.col(j * nx + i + 1) +
                  grid.positions.col((j + 1) * nx + i) + grid.positions.col((j + 1) * nx + i + 1));
      EXPECT_TRUE(grid.positions.col(centre).isApprox(expected));
      EXPECT_TRUE(grid.uvs.col(centre).isApprox(Vec2((i + 0.5) / 3.0, (j + 0.5) / 2.0)));
    }
  }
}

TEST(MakeGrid, FrontFacesPlusZ) {
  for (const auto triangulation : all_triangulations) {
    const TriangleMesh grid = make_grid(5, 4, 2.0, 1.0, triangulation);
    for (int t = 0; t < grid.num_triangles(); ++t) {
      const Vec3 normal = area_normal(grid, t);
      EXPECT_GT(normal.z(), 0.0) << "triangle " << t;
      EXPECT_NEAR(normal.x(), 0.0, 1e-14);
      EXPECT_NEAR(normal.y(), 0.0, 1e-14);
    }
  }
}

TEST(MakeGrid, DiagonalsFollowTheTriangulation) {
  // Quad (0, 0) of a 3 x 2 grid has corners 0, 1, 4, 3; quad (1, 0) has 1, 2, 5, 4.
  const auto has_edge = [](const TriangleMesh& grid, int a, int b) {
    const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
    for (int e = 0; e < topology.num_edges(); ++e) {
      if (topology.edges(0, e) == std::min(a, b) && topology.edges(1, e) == std::max(a, b)) return true;
    }
    return false;
  };
  const TriangleMesh regular = make_grid(3, 2, 1.0, 1.0, GridTriangulation::regular);
  EXPECT_TRUE(has_edge(regular, 0, 4));
  EXPECT_TRUE(has_edge(regular, 1, 5));
  EXPECT_FALSE(has_edge(regular, 2, 4));
  const TriangleMesh alternating = make_grid(3, 2, 1.0, 1.0, GridTriangulation::alternating);
  EXPECT_TRUE(has_edge(alternating, 0, 4));
  EXPECT_TRUE(has_edge(alternating, 2, 4));
  EXPECT_FALSE(has_edge(alternating, 1, 5));
  const TriangleMesh cross = make_grid(3, 2, 1.0, 1.0, GridTriangulation::cross);
  EXPECT_FALSE(has_edge(cross, 0, 4));
  EXPECT_FALSE(has_edge(cross, 1, 3));
  for (const int corner : {0, 1, 4, 3}) EXPECT_TRUE(has_edge(cross, corner, 6));
}

TEST(MakeUvSphere, VerticesOnTheSphereAndOutward) {
  const double radius = 1.5;
  const int slices = 10, stacks = 6;
  const TriangleMesh sphere = make_uv_sphere(radius, slices, stacks);
  EXPECT_EQ(sphere.num_vertices(), 2 + slices * (stacks - 1));
  EXPECT_EQ(sphere.num_triangles(), 2 * slices * (stacks - 1));
  EXPECT_FALSE(sphere.has_uvs());
  for (int v = 0; v < sphere.num_vertices(); ++v) EXPECT_NEAR(sphere.positions.col(v).norm(), radius, 1e-12);
  EXPECT_TRUE(sphere.positions.col(0).isApprox(Vec3(0.0, radius, 0.0)));
  EXPECT_TRUE(sphere.positions.col(sphere.num_vertices() - 1).isApprox(Vec3(0.0, -radius, 0.0)));
  expect_every_triangle_outward(sphere);
  EXPECT_GT(signed_volume(sphere), 0.0);
}

TEST(MakeUvSphere, VolumeConvergesToTheBall) {
  const double radius = 0.7;
  const double ball = 4.0 / 3.0 * pi * radius * radius * radius;
  const double coarse = signed_volume(make_uv_sphere(radius, 16, 8));
  const double fine = signed_volume(make_uv_sphere(radius, 128, 64));
  EXPECT_LT(coarse, ball);
  EXPECT_LT(fine, ball);
  EXPECT_LT(ball - fine, 0.1 * (ball - coarse));
  EXPECT_NEAR(fine, ball, 2e-3 * ball);
}

TEST(MakeBox, CornersAndVolume) {
  const Vec3 half_extents(0.5, 1.0, 2.0);
  const TriangleMesh box = make_box(half_extents);
  ASSERT_EQ(box.num_vertices(), 8);
  ASSERT_EQ(box.num_triangles(), 12);
  for (int v = 0; v < 8; ++v) EXPECT_TRUE(box.positions.col(v).cwiseAbs().isApprox(half_extents));
  expect_every_triangle_outward(box);
  EXPECT_NEAR(signed_volume(box), 8.0 * 0.5 * 1.0 * 2.0, 1e-12);
  // Each face's two triangles lie in that face: their normals are axis aligned.
  for (int t = 0; t < 12; ++t) {
    const Vec3 normal = area_normal(box, t).normalized();
    EXPECT_NEAR(normal.cwiseAbs().maxCoeff(), 1.0, 1e-12) << "triangle " << t;
  }
}

TEST(MakeCylinder, CappedIsClosedAndOutward) {
  const double radius = 0.5, height = 2.0;
  const int segments = 12;
  const TriangleMesh cylinder = make_cylinder(radius, height, segments, true);
  EXPECT_EQ(cylinder.num_vertices(), 2 * segments + 2);
  EXPECT_EQ(cylinder.num_triangles(), 4 * segments);
  expect_every_triangle_outward(cylinder);
  // Exactly a prism over a regular polygon of area (n/2) r^2 sin(2 pi / n).
  const double polygon_area = 0.5 * segments * radius * radius * std::sin(2.0 * pi / segments);
  EXPECT_NEAR(signed_volume(cylinder), polygon_area * height, 1e-12);
  for (int v = 0; v < 2 * segments; ++v) {
    EXPECT_NEAR(Vec2(cylinder.positions(0, v), cylinder.positions(2, v)).norm(), radius, 1e-12);
    EXPECT_NEAR(std::abs(cylinder.positions(1, v)), 0.5 * height, 1e-12);
  }
}

TEST(MakeCylinder, OpenTubeFacesOutward) {
  const TriangleMesh tube = make_cylinder(0.5, 2.0, 7, false);
  EXPECT_EQ(tube.num_vertices(), 14);
  EXPECT_EQ(tube.num_triangles(), 14);
  for (int t = 0; t < tube.num_triangles(); ++t) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 3; ++k) centroid += tube.positions.col(tube.triangles(k, t)) / 3.0;
    centroid.y() = 0.0;
    EXPECT_GT(area_normal(tube, t).dot(centroid), 0.0) << "triangle " << t;
    EXPECT_NEAR(area_normal(tube, t).y(), 0.0, 1e-12);
  }
}

TEST(MeshGenerators, RejectBadArguments) {
  expect_invalid_argument([] { make_grid(1, 4, 1.0, 1.0, GridTriangulation::regular); }, "nx");
  expect_invalid_argument([] { make_grid(4, 0, 1.0, 1.0, GridTriangulation::regular); }, "ny");
  expect_invalid_argument([] { make_grid(4, 4, 0.0, 1.0, GridTriangulation::cross); }, "width");
  expect_invalid_argument([] { make_grid(4, 4, 1.0, std::nan(""), GridTriangulation::cross); }, "height");
  expect_invalid_argument([] { make_grid(100000, 100000, 1.0, 1.0, GridTriangulation::cross); }, "too large");
  expect_invalid_argument([] { make_uv_sphere(-1.0, 8, 4); }, "radius");
  expect_invalid_argument([] { make_uv_sphere(1.0, 2, 4); }, "slices");
  expect_invalid_argument([] { make_uv_sphere(1.0, 8, 1); }, "stacks");
  expect_invalid_argument([] { make_box(Vec3(1.0, 0.0, 1.0)); }, "half_extents.y");
  expect_invalid_argument([] { make_box(Vec3(1.0, 1.0, INFINITY)); }, "half_extents.z");
  expect_invalid_argument([] { make_cylinder(1.0, 1.0, 2, true); }, "segments");
  expect_invalid_argument([] { make_cylinder(1.0, -2.0, 8, false); }, "height");
}

}  // namespace
}  // namespace weft
