// Edge and hinge connectivity: counts on grids and closed solids, and every record checked
// against the triangles it was built from.
#include "core/topology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "core/mesh_generators.hpp"

namespace weft {
namespace {

bool triangle_has(const Triangles& triangles, int t, int v) {
  return triangles(0, t) == v || triangles(1, t) == v || triangles(2, t) == v;
}

// Checks every field of `topology` against `triangles`.
void expect_consistent(const MeshTopology& topology, const Triangles& triangles) {
  // Edges: smaller vertex first, strictly increasing, so unique.
  for (int e = 0; e < topology.num_edges(); ++e) {
    ASSERT_LT(topology.edges(0, e), topology.edges(1, e)) << "edge " << e;
    if (e > 0) {
      const auto previous = std::make_pair(topology.edges(0, e - 1), topology.edges(1, e - 1));
      ASSERT_LT(previous, std::make_pair(topology.edges(0, e), topology.edges(1, e))) << "edge " << e;
    }
  }

  // Side k of triangle t joins its vertices k and k+1, and t is listed at that edge.
  std::vector<int> triangles_at_edge(topology.num_edges(), 0);
  for (int t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int e = topology.triangle_edges(k, t);
      const int a = std::min(triangles(k, t), triangles((k + 1) % 3, t));
      const int b = std::max(triangles(k, t), triangles((k + 1) % 3, t));
      ASSERT_EQ(topology.edges(0, e), a);
      ASSERT_EQ(topology.edges(1, e), b);
      ++triangles_at_edge[e];
    }
  }
  for (int e = 0; e < topology.num_edges(); ++e) {
    for (int s = 0; s < std::min(2, triangles_at_edge[e]); ++s) {
      const int t = topology.edge_triangles(s, e);
      ASSERT_TRUE(triangle_has(triangles, t, topology.edges(0, e)) &&
                  triangle_has(triangles, t, topology.edges(1, e)));
    }
    if (triangles_at_edge[e] < 2) {
      EXPECT_EQ(topology.edge_triangles(1, e), -1);
    }
    const bool boundary = std::count(topology.boundary_edges.begin(), topology.boundary_edges.end(), e) == 1;
    const bool non_manifold =
        std::count(topology.non_manifold_edges.begin(), topology.non_manifold_edges.end(), e) == 1;
    EXPECT_EQ(boundary, triangles_at_edge[e] == 1) << "edge " << e;
    EXPECT_EQ(non_manifold, triangles_at_edge[e] >= 3) << "edge " << e;
  }

  // Hinges: v0 v1 the edge, v2 and v3 the other vertices of its two triangles, (v0, v1, v2) a
  // rotation of the first triangle.
  ASSERT_EQ(topology.hinge_edges.size(), topology.num_hinges());
  for (int h = 0; h < topology.num_hinges(); ++h) {
    const int e = topology.hinge_edges[h];
    ASSERT_EQ(triangles_at_edge[e], 2);
    const Eigen::Vector4i hinge = topology.hinges.col(h);
    EXPECT_EQ(std::min(hinge[0], hinge[1]), topology.edges(0, e));
    EXPECT_EQ(std::max(hinge[0], hinge[1]), topology.edges(1, e));
    const int t0 = topology.edge_triangles(0, e);
    const int t1 = topology.edge_triangles(1, e);
    EXPECT_TRUE(triangle_has(triangles, t0, hinge[2]));
    EXPECT_TRUE(triangle_has(triangles, t1, hinge[3]));
    EXPECT_NE(hinge[2], hinge[0]);
    EXPECT_NE(hinge[2], hinge[1]);
    EXPECT_NE(hinge[3], hinge[0]);
    EXPECT_NE(hinge[3], hinge[1]);
    EXPECT_NE(hinge[2], hinge[3]);
    bool rotation_of_first = false;
    for (int k = 0; k < 3; ++k) {
      rotation_of_first |= triangles(k, t0) == hinge[0] && triangles((k + 1) % 3, t0) == hinge[1] &&
                           triangles((k + 2) % 3, t0) == hinge[2];
    }
    EXPECT_TRUE(rotation_of_first) << "hinge " << h;
  }

  // Triangles around each vertex: exactly those with it as a corner, in increasing order.
  ASSERT_FALSE(topology.vertex_triangle_start.empty());
  const int num_vertices = static_cast<int>(topology.vertex_triangle_start.size()) - 1;
  ASSERT_EQ(topology.vertex_triangles.size(), 3 * static_cast<size_t>(triangles.cols()));
  for (int v = 0; v < num_vertices; ++v) {
    std::vector<int> expected;
    for (int t = 0; t < triangles.cols(); ++t) {
      if (triangle_has(triangles, t, v)) expected.push_back(t);
    }
    const std::vector<int> around(topology.vertex_triangles.begin() + topology.vertex_triangle_start[v],
                                  topology.vertex_triangles.begin() + topology.vertex_triangle_start[v + 1]);
    EXPECT_EQ(around, expected) << "vertex " << v;
  }
}

int euler_characteristic(const MeshTopology& topology, int num_vertices, int num_triangles) {
  return num_vertices - topology.num_edges() + num_triangles;
}

TEST(Topology, SingleTriangleIsAllBoundary) {
  Triangles triangles(3, 1);
  triangles << 2, 0, 1;
  const MeshTopology topology = build_topology(triangles, 3);
  ASSERT_EQ(topology.num_edges(), 3);
  EXPECT_EQ(topology.edges, (Eigen::Matrix2Xi(2, 3) << 0, 0, 1, 1, 2, 2).finished());
  EXPECT_EQ(topology.boundary_edges, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(topology.num_hinges(), 0);
  // Side 0 joins 2-0 (edge 1), side 1 joins 0-1 (edge 0), side 2 joins 1-2 (edge 2).
  EXPECT_EQ(topology.triangle_edges.col(0), Vec3i(1, 0, 2));
  expect_consistent(topology, triangles);
}

TEST(Topology, TwoTrianglesShareOneHinge) {
  // Square 0-1-2-3 cut along 0-2.
  Triangles triangles(3, 2);
  triangles << 0, 0, 1, 2, 2, 3;
  const MeshTopology topology = build_topology(triangles, 4);
  ASSERT_EQ(topology.num_edges(), 5);
  ASSERT_EQ(topology.num_hinges(), 1);
  EXPECT_EQ(topology.boundary_edges.size(), 4u);
  EXPECT_EQ(topology.hinges.col(0), Eigen::Vector4i(2, 0, 1, 3));
  const int e = topology.hinge_edges[0];
  EXPECT_EQ(topology.edges.col(e), Eigen::Vector2i(0, 2));
  EXPECT_EQ(topology.edge_triangles.col(e), Eigen::Vector2i(0, 1));
  expect_consistent(topology, triangles);
}

TEST(Topology, GridsAreDiscs) {
  for (const auto triangulation :
       {GridTriangulation::regular, GridTriangulation::alternating, GridTriangulation::cross}) {
    for (const auto& [nx, ny] : {std::pair{2, 2}, {3, 5}, {7, 4}, {16, 16}}) {
      SCOPED_TRACE(::testing::Message() << nx << " x " << ny << " triangulation " << int(triangulation));
      const TriangleMesh grid = make_grid(nx, ny, 2.0, 1.0, triangulation);
      const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
      EXPECT_EQ(euler_characteristic(topology, grid.num_vertices(), grid.num_triangles()), 1);
      EXPECT_EQ(static_cast<int>(topology.boundary_edges.size()), 2 * (nx - 1) + 2 * (ny - 1));
      EXPECT_EQ(topology.num_hinges(),
                topology.num_edges() - static_cast<int>(topology.boundary_edges.size()));
      EXPECT_TRUE(topology.non_manifold_edges.empty());
      expect_consistent(topology, grid.triangles);
    }
  }
}

TEST(Topology, ClosedSolidsHaveNoBoundary) {
  const std::pair<const char*, TriangleMesh> solids[] = {
      {"sphere", make_uv_sphere(1.0, 12, 7)},
      {"coarse sphere", make_uv_sphere(1.0, 3, 2)},
      {"box", make_box(Vec3(1.0, 2.0, 3.0))},
      {"capped cylinder", make_cylinder(0.5, 2.0, 9, true)},
  };
  for (const auto& [name, mesh] : solids) {
    SCOPED_TRACE(name);
    const MeshTopology topology = build_topology(mesh.triangles, mesh.num_vertices());
    EXPECT_TRUE(topology.boundary_edges.empty());
    EXPECT_TRUE(topology.non_manifold_edges.empty());
    EXPECT_EQ(euler_characteristic(topology, mesh.num_vertices(), mesh.num_triangles()), 2);
    EXPECT_EQ(topology.num_hinges(), topology.num_edges());
    expect_consistent(topology, mesh.triangles);
  }
}

TEST(Topology, OpenCylinderIsATube) {
  const int segments = 11;
  const TriangleMesh tube = make_cylinder(0.5, 2.0, segments, false);
  const MeshTopology topology = build_topology(tube.triangles, tube.num_vertices());
  EXPECT_EQ(static_cast<int>(topology.boundary_edges.size()), 2 * segments);
  EXPECT_EQ(euler_characteristic(topology, tube.num_vertices(), tube.num_triangles()), 0);
  expect_consistent(topology, tube.triangles);
}

TEST(Topology, ConsistentWindingPutsTheSecondTriangleBackwards) {
  // In an oriented mesh the second triangle of a hinge runs (v1, v0, v3).
  const TriangleMesh sphere = make_uv_sphere(1.0, 8, 5);
  const MeshTopology topology = build_topology(sphere.triangles, sphere.num_vertices());
  for (int h = 0; h < topology.num_hinges(); ++h) {
    const int t1 = topology.edge_triangles(1, topology.hinge_edges[h]);
    bool backwards = false;
    for (int k = 0; k < 3; ++k) {
      backwards |= sphere.triangles(k, t1) == topology.hinges(1, h) &&
                   sphere.triangles((k + 1) % 3, t1) == topology.hinges(0, h) &&
                   sphere.triangles((k + 2) % 3, t1) == topology.hinges(3, h);
    }
    EXPECT_TRUE(backwards) << "hinge " << h;
  }
}

TEST(Topology, ThreeTrianglesOnAnEdgeAreNonManifold) {
  Triangles triangles(3, 3);
  triangles << 0, 1, 0,  //
      1, 0, 1,           //
      2, 3, 4;
  const MeshTopology topology = build_topology(triangles, 5);
  ASSERT_EQ(topology.non_manifold_edges.size(), 1u);
  const int e = topology.non_manifold_edges[0];
  EXPECT_EQ(topology.edges.col(e), Eigen::Vector2i(0, 1));
  EXPECT_EQ(topology.edge_triangles.col(e), Eigen::Vector2i(0, 1));
  EXPECT_EQ(topology.num_hinges(), 0);
  EXPECT_EQ(topology.boundary_edges.size(), 6u);
  expect_consistent(topology, triangles);
}

TEST(Topology, LargeGrid) {
  const TriangleMesh grid = make_grid(256, 256, 1.0, 1.0, GridTriangulation::alternating);
  const MeshTopology topology = build_topology(grid.triangles, grid.num_vertices());
  const int expected_edges = 255 * 256 * 2 + 255 * 255;
  EXPECT_EQ(topology.num_edges(), expected_edges);
  EXPECT_EQ(static_cast<int>(topology.boundary_edges.size()), 4 * 255);
  EXPECT_EQ(topology.num_hinges(), expected_edges - 4 * 255);
}

TEST(Topology, EmptyMesh) {
  const MeshTopology topology = build_topology(Triangles(3, 0), 4);
  EXPECT_EQ(topology.num_edges(), 0);
  EXPECT_EQ(topology.num_hinges(), 0);
  EXPECT_EQ(topology.triangle_edges.cols(), 0);
}

TEST(Topology, RejectsBadTriangles) {
  Triangles out_of_range(3, 1);
  out_of_range << 0, 1, 3;
  EXPECT_THROW(build_topology(out_of_range, 3), std::invalid_argument);
  Triangles negative(3, 1);
  negative << 0, -1, 2;
  EXPECT_THROW(build_topology(negative, 3), std::invalid_argument);
  Triangles repeated(3, 1);
  repeated << 0, 1, 0;
  try {
    build_topology(repeated, 3);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("repeats"), std::string::npos) << error.what();
  }
  EXPECT_THROW(build_topology(Triangles(3, 0), -1), std::invalid_argument);
}

}  // namespace
}  // namespace weft
