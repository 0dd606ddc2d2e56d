#include "render/loop_subdivision.hpp"

#include <gtest/gtest.h>

#include "core/mesh_generators.hpp"
#include "core/topology.hpp"

namespace weft {
namespace {

// Each round adds one vertex per edge and splits every triangle in four.
TEST(LoopSubdivision, CountsOnAGrid) {
  const TriangleMesh grid = make_grid(5, 4, 1.0, 1.0, GridTriangulation::alternating);
  int vertices = grid.num_vertices(), triangles = grid.num_triangles();
  int edges = build_topology(grid.triangles, vertices).num_edges();
  for (int levels = 0; levels <= 2; ++levels) {
    const LoopSubdivision subdivision = make_loop_subdivision(grid.triangles, grid.num_vertices(), levels);
    EXPECT_EQ(subdivision.num_fine_vertices(), vertices) << levels;
    EXPECT_EQ(subdivision.triangles.cols(), triangles) << levels;
    EXPECT_EQ(subdivision.coarse_to_fine.cols(), grid.num_vertices());
    EXPECT_EQ(build_topology(subdivision.triangles, vertices).num_edges(), edges) << levels;
    // Next round: E new vertices, 4F triangles, 2E + 3F edges.
    vertices += edges;
    const int next_edges = 2 * edges + 3 * triangles;
    triangles *= 4;
    edges = next_edges;
  }
}

// Weights are affine (each row sums to 1): a translated mesh subdivides to the translated result,
// a flat mesh stays flat, and the grid's corners (one triangle each) do not move.
TEST(LoopSubdivision, AffineWeightsKeepAFlatGridFlatAndItsCorners) {
  const TriangleMesh grid = make_grid(4, 4, 2.0, 2.0, GridTriangulation::regular);
  const LoopSubdivision subdivision = make_loop_subdivision(grid.triangles, grid.num_vertices(), 2);
  const Eigen::VectorXd row_sums = subdivision.coarse_to_fine * Eigen::VectorXd::Ones(grid.num_vertices());
  EXPECT_TRUE(row_sums.isApprox(Eigen::VectorXd::Ones(subdivision.num_fine_vertices()), 1e-12));
  const Positions fine = subdivision.apply(grid.positions);
  EXPECT_LT(fine.row(2).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE(fine.row(0).cwiseAbs().maxCoeff(), 1.0 + 1e-12);
  // make_grid's regular diagonal leaves two corners in a single triangle.
  for (int corner : {0, 3, 12, 15}) {
    int triangles_at_corner = 0;
    for (int t = 0; t < grid.num_triangles(); ++t) triangles_at_corner += (grid.triangles.col(t).array() == corner).any();
    if (triangles_at_corner == 1) {
      EXPECT_TRUE(fine.col(corner).isApprox(grid.positions.col(corner))) << corner;
    }
  }
}

// A closed mesh stays closed: every fine edge has two triangles, and Euler's V - E + F is kept.
TEST(LoopSubdivision, ClosedSphereStaysClosedAndShrinksInside) {
  const TriangleMesh sphere = make_uv_sphere(1.0, 12, 8);
  const LoopSubdivision subdivision = make_loop_subdivision(sphere.triangles, sphere.num_vertices(), 1);
  const MeshTopology topology = build_topology(subdivision.triangles, subdivision.num_fine_vertices());
  EXPECT_TRUE(topology.boundary_edges.empty());
  EXPECT_EQ(subdivision.num_fine_vertices() - topology.num_edges() + subdivision.triangles.cols(), 2);
  // Loop's masks average neighbours: the limit surface lies inside a convex control mesh.
  const Positions fine = subdivision.apply(sphere.positions);
  EXPECT_LE(fine.colwise().norm().maxCoeff(), 1.0 + 1e-12);
  EXPECT_GT(fine.colwise().norm().minCoeff(), 0.8);
}

}  // namespace
}  // namespace weft
