// Untangler: the edges through triangles of a combined mesh, and the pushes that take the side
// that passed through back, judged by the exact intersection check (check/intersection_check.hpp),
// which shares no code with it.
#include "collision/untangling.hpp"

#include <gtest/gtest.h>

#include <omp.h>

#include "check/intersection_check.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

// Two n x n sheets in one combined mesh: `flat` in the plane y = 0, `tilted` rotated about x by
// `tilt_degrees` and lifted by `lift`, so that its low edge passes below the flat one.
struct TwoSheets {
  Positions x;
  Triangles triangles;
  std::vector<int> vertex_mesh;
  int flat_triangles = 0;
};

TwoSheets crossed_sheets(int n, double tilt_degrees, double lift, double shift_x) {
  const TriangleMesh grid = make_grid(n, n, 0.6, 0.6, GridTriangulation::alternating);
  const int v = grid.num_vertices();
  const int t = grid.num_triangles();
  TwoSheets sheets;
  sheets.x.resize(3, 2 * v);
  sheets.triangles.resize(3, 2 * t);
  const Mat3 lay = Eigen::AngleAxisd(-0.5 * M_PI, Vec3::UnitX()).toRotationMatrix();  // XY plane to XZ
  const Mat3 tilt = Eigen::AngleAxisd(tilt_degrees * M_PI / 180.0, Vec3::UnitX()).toRotationMatrix();
  for (int i = 0; i < v; ++i) {
    sheets.x.col(i) = lay * grid.positions.col(i);
    sheets.x.col(v + i) = tilt * lay * grid.positions.col(i) + Vec3(shift_x, lift, 0.03);
  }
  sheets.triangles.leftCols(t) = grid.triangles;
  sheets.triangles.rightCols(t) = grid.triangles.array() + v;
  sheets.vertex_mesh.assign(static_cast<size_t>(v), 0);
  sheets.vertex_mesh.insert(sheets.vertex_mesh.end(), static_cast<size_t>(v), 1);
  sheets.flat_triangles = t;
  return sheets;
}

size_t exact_pairs(const Positions& x, const Triangles& triangles) {
  return find_triangle_intersections(x, triangles).size();
}

// Passes of find_crossings and plan_pushes, as the World runs them, until none is left.
int untangle(Untangler& untangler, Positions& x, const Eigen::VectorXd& inverse_mass, int max_passes = 8) {
  const Eigen::VectorXd margin = Eigen::VectorXd::Constant(x.cols(), 5e-4);
  Positions push;
  for (int pass = 0; pass < max_passes; ++pass) {
    if (untangler.find_crossings(x).empty()) return pass;
    const UntanglePass result = untangler.plan_pushes(x, inverse_mass, margin, push);
    if (result.moved_vertices == 0) return -1;
    x += push;
  }
  return untangler.find_crossings(x).empty() ? max_passes : -1;
}

TEST(Untangler, FindsTheEdgesOfTwoCrossedSheetsThroughEachOther) {
  TwoSheets sheets = crossed_sheets(13, 10.0, 0.04, 0.05);
  ASSERT_GT(exact_pairs(sheets.x, sheets.triangles), 0u);
  Untangler untangler;
  untangler.set_mesh(sheets.triangles, sheets.vertex_mesh);
  const auto& crossings = untangler.find_crossings(sheets.x);
  ASSERT_FALSE(crossings.empty());
  for (const EdgeThroughTriangle& c : crossings) {
    const int a = untangler.edges()(0, c.edge);
    // An edge of one sheet through a triangle of the other: the sheets do not cross themselves.
    EXPECT_NE(sheets.vertex_mesh[a], sheets.vertex_mesh[sheets.triangles(0, c.triangle)]);
  }
  // The same list on any number of threads.
  const std::vector<EdgeThroughTriangle> many = crossings;
  omp_set_num_threads(1);
  const auto& one = untangler.find_crossings(sheets.x);
  omp_set_num_threads(omp_get_num_procs());
  ASSERT_EQ(one.size(), many.size());
  for (size_t k = 0; k < one.size(); ++k) {
    EXPECT_EQ(one[k].edge, many[k].edge);
    EXPECT_EQ(one[k].triangle, many[k].triangle);
  }
}

TEST(Untangler, MovesTheSmallerSideBackAndLeavesTheSheetsClean) {
  TwoSheets sheets = crossed_sheets(13, 10.0, 0.04, 0.05);
  const Positions before = sheets.x;
  Untangler untangler;
  untangler.set_mesh(sheets.triangles, sheets.vertex_mesh);
  const Eigen::VectorXd inverse_mass = Eigen::VectorXd::Ones(sheets.x.cols());
  EXPECT_GE(untangle(untangler, sheets.x, inverse_mass), 1);
  EXPECT_EQ(exact_pairs(sheets.x, sheets.triangles), 0u);
  // One side of the crossing moved, a strip along one edge: the tilted sheet's strip below the
  // flat one, or the flat sheet's edge above it (both undo the crossing; the smaller moves).
  const int n = 13 * 13;
  int moved = 0;
  for (int i = 0; i < 2 * n; ++i) moved += (sheets.x.col(i) - before.col(i)).norm() > 0.0;
  EXPECT_GT(moved, 0);
  EXPECT_LT(moved, n / 4);
}

TEST(Untangler, APinnedSideStaysAndTheOtherSideMoves) {
  TwoSheets sheets = crossed_sheets(13, 10.0, 0.04, 0.05);
  const Positions before = sheets.x;
  Untangler untangler;
  untangler.set_mesh(sheets.triangles, sheets.vertex_mesh);
  Eigen::VectorXd inverse_mass = Eigen::VectorXd::Ones(sheets.x.cols());
  const int n = 13 * 13;
  for (int i = n; i < 2 * n; ++i) {
    if (before(1, i) < 0.0) inverse_mass(i) = 0.0;  // the strip below the flat sheet is pinned
  }
  EXPECT_GE(untangle(untangler, sheets.x, inverse_mass), 1);
  EXPECT_EQ(exact_pairs(sheets.x, sheets.triangles), 0u);
  for (int i = 0; i < 2 * n; ++i) {
    if (inverse_mass(i) == 0.0) EXPECT_EQ(sheets.x.col(i), before.col(i));
  }
  EXPECT_NE(sheets.x.leftCols(n), before.leftCols(n)) << "the flat sheet should have moved instead";
}

TEST(Untangler, ACleanMeshIsLeftAlone) {
  TwoSheets sheets = crossed_sheets(13, 10.0, 0.2, 0.05);  // the tilted sheet wholly above
  ASSERT_EQ(exact_pairs(sheets.x, sheets.triangles), 0u);
  Untangler untangler;
  untangler.set_mesh(sheets.triangles, sheets.vertex_mesh);
  EXPECT_TRUE(untangler.find_crossings(sheets.x).empty());
  Positions push;
  const UntanglePass pass = untangler.plan_pushes(sheets.x, Eigen::VectorXd::Ones(sheets.x.cols()),
                                                  Eigen::VectorXd::Constant(sheets.x.cols(), 5e-4), push);
  EXPECT_EQ(pass.moved_vertices, 0);
  EXPECT_TRUE(push.isZero(0.0));
}

TEST(Untangler, AFlapFoldedThroughItsSheetIsFoldedBack) {
  // One strip of 41 x 5 vertices, 0.5 m long: flat for x in [0, 0.3], then a flap sloping back
  // over it from x = 0.3 at a height of 2 cm down through the flat part (at x = 0.19) to 1.5 cm
  // below it at x = 0.1. The flap's tip beyond the crossing is the smaller side.
  const int nu = 41;
  const int nz = 5;
  const int flat_rows = 25;  // u <= 0.3
  Positions x(3, nu * nz);
  for (int i = 0; i < nu; ++i) {
    const double u = 0.5 * i / (nu - 1);
    const Vec3 centre = u <= 0.3 ? Vec3(u, 0.0, 0.0) : Vec3(0.6 - u, 0.02 - 0.035 * (u - 0.3) / 0.2, 0.0);
    for (int j = 0; j < nz; ++j) x.col(i * nz + j) = centre + Vec3(0.0, 0.0, 0.05 * j);
  }
  Triangles triangles(3, 2 * (nu - 1) * (nz - 1));
  int t = 0;
  for (int i = 0; i + 1 < nu; ++i) {
    for (int j = 0; j + 1 < nz; ++j) {
      const int a = i * nz + j;
      triangles.col(t++) = Vec3i(a, a + nz, a + nz + 1);
      triangles.col(t++) = Vec3i(a, a + nz + 1, a + 1);
    }
  }
  ASSERT_GT(exact_pairs(x, triangles), 0u);
  Untangler untangler;
  untangler.set_mesh(triangles, std::vector<int>(static_cast<size_t>(nu * nz), 0));
  const Positions before = x;
  EXPECT_GE(untangle(untangler, x, Eigen::VectorXd::Ones(x.cols())), 1);
  EXPECT_EQ(exact_pairs(x, triangles), 0u);
  // The flat part stayed; the flap's tip rose above it.
  EXPECT_EQ(x.leftCols(flat_rows * nz), before.leftCols(flat_rows * nz));
  EXPECT_GT(x(1, (nu - 1) * nz), 0.0);
}

}  // namespace
}  // namespace weft
