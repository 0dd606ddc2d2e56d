// The tangle check on tiny inline states: two crossing triangles of two cloths, a folded cloth
// through itself, a cloth triangle through a collider's, vertices inside a solid with the
// deepest named, and a clean state reporting nothing; pairs among colliders never count.
#include <gtest/gtest.h>

#include <cmath>

#include "check/tangle_check.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

// A triangle (3 corners) as a mesh.
struct OneTriangle {
  Positions x;
  Triangles triangles;
  OneTriangle(const Vec3& a, const Vec3& b, const Vec3& c) : x(3, 3), triangles(3, 1) {
    x << a, b, c;
    triangles << 0, 1, 2;
  }
};

TEST(TangleCheck, CrossingClothsAreCountedNamedAndPlaced) {
  const OneTriangle flat(Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1));
  const OneTriangle upright(Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(0, 0, 0.5));
  TangleInput input;
  input.cloths = {{"flat", &flat.x, &flat.triangles}, {"upright", &upright.x, &upright.triangles}};
  const TangleReport report = check_tangles(input);
  EXPECT_EQ(report.intersecting_pairs, 1);
  EXPECT_EQ(report.vertices_inside_colliders, 0);
  ASSERT_EQ(report.surface_pairs.size(), 1u);
  EXPECT_EQ(report.surface_pairs[0].surface_a, 0);
  EXPECT_EQ(report.surface_pairs[0].surface_b, 1);
  EXPECT_EQ(describe_tangles(report, input),
            "cloths \"flat\" and \"upright\": 1 intersecting triangle pair (first: triangles 0 and 0 near "
            "(0.00, 0.00, -0.08))");
}

TEST(TangleCheck, ColliderPairsAmongThemselvesDoNotCountButClothThroughColliderDoes) {
  const OneTriangle a(Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(0, 0, 1));
  const OneTriangle b(Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(0, 0, 0.5));
  TangleInput colliders_only;
  colliders_only.colliders = {{"a", &a.x, &a.triangles}, {"b", &b.x, &b.triangles}};
  EXPECT_TRUE(check_tangles(colliders_only).clean());

  TangleInput cloth_and_collider;
  cloth_and_collider.cloths = {{"sheet", &a.x, &a.triangles}};
  cloth_and_collider.colliders = {{"post", &b.x, &b.triangles}};
  const TangleReport report = check_tangles(cloth_and_collider);
  EXPECT_EQ(report.intersecting_pairs, 1);
  EXPECT_NE(describe_tangles(report, cloth_and_collider).find("cloth \"sheet\" and collider \"post\""),
            std::string::npos);
}

TEST(TangleCheck, AFlatGridIsCleanAndAFoldThroughItselfIsNot) {
  const TriangleMesh grid = make_grid(9, 3, 1.0, 0.25, GridTriangulation::regular);
  TangleInput input;
  input.cloths = {{"grid", &grid.positions, &grid.triangles}};
  EXPECT_TRUE(check_tangles(input).clean());
  EXPECT_EQ(describe_tangles(check_tangles(input), input), "");

  // The half x > 0 folded back over the other by 160 degrees about x = 0, then lowered 10 cm:
  // it passes through the unfolded half.
  Positions folded = grid.positions;
  const double angle = 160.0 * M_PI / 180.0;
  for (int v = 0; v < folded.cols(); ++v) {
    const double x = grid.positions(0, v);
    if (x <= 0.0) continue;
    folded(0, v) = x * std::cos(angle);
    folded(2, v) = x * std::sin(angle) - 0.1;
  }
  input.cloths[0].positions = &folded;
  const TangleReport report = check_tangles(input);
  EXPECT_GT(report.intersecting_pairs, 0);
  EXPECT_NE(describe_tangles(report, input).find("cloth \"grid\" through itself"), std::string::npos);
}

TEST(TangleCheck, VerticesInsideASolidAreCountedWithTheDeepest) {
  Positions x(3, 4);
  x << 0, 0.1, 0.9, 0.0,  //
      0.45, 0.2, 0, 2.0,  //
      0, 0, 0, 0;
  Triangles triangles(3, 0);
  AnalyticSolid sphere;
  sphere.kind = SolidKind::sphere;
  sphere.radius = 0.5;
  const OneTriangle surface(Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5));  // far away
  TangleInput input;
  input.cloths = {{"points", &x, &triangles}};
  input.colliders = {{"ball", &surface.x, &surface.triangles}};
  input.solids = {sphere};
  input.solid_collider = {0};
  const TangleReport report = check_tangles(input);
  EXPECT_EQ(report.vertices_inside_colliders, 2);
  ASSERT_EQ(report.inside.size(), 1u);
  EXPECT_EQ(report.inside[0].deepest_vertex, 1);
  EXPECT_NEAR(report.inside[0].deepest, 0.5 - std::sqrt(0.05), 1e-15);
  EXPECT_NE(describe_tangles(report, input)
                .find("cloth \"points\": 2 vertices inside collider \"ball\" (deepest: vertex 1"),
            std::string::npos);
}

TEST(TangleCheck, AClothHeldInsideASolidIsNotCountedAsInsideIt) {
  // Three of four vertices inside the ball: the ball holds the cloth (a drum), so none count.
  Positions x(3, 4);
  x << 0, 0.1, 0.2, 0.9,  //
      0, 0, 0, 0,         //
      0, 0, 0, 0;
  Triangles triangles(3, 0);
  AnalyticSolid ball;
  ball.kind = SolidKind::sphere;
  ball.radius = 0.5;
  const OneTriangle surface(Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5));
  TangleInput input;
  input.cloths = {{"held", &x, &triangles}};
  input.colliders = {{"drum", &surface.x, &surface.triangles}};
  input.solids = {ball};
  input.solid_collider = {0};
  EXPECT_EQ(check_tangles(input).vertices_inside_colliders, 3);
  input.held = solids_holding_cloths(input);
  ASSERT_EQ(input.held.size(), 1u);
  EXPECT_EQ(input.held[0], std::vector<char>{1});
  EXPECT_TRUE(check_tangles(input).clean());
}

}  // namespace
}  // namespace weft
