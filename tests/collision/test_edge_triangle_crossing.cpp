// edge_triangle_crossing: where a segment passes through a triangle, and the configurations that
// are no crossing (an end on the plane, a segment beside the triangle or in its plane, a needle).
#include "collision/edge_triangle_crossing.hpp"

#include <gtest/gtest.h>

namespace weft {
namespace {

const Vec3 p(0.0, 0.0, 0.0);
const Vec3 q(1.0, 0.0, 0.0);
const Vec3 r(0.0, 1.0, 0.0);

TEST(EdgeTriangleCrossing, ASegmentThroughTheInteriorCrossesWhereItMeetsThePlane) {
  const auto crossing = edge_triangle_crossing(Vec3(0.2, 0.3, -1.0), Vec3(0.2, 0.3, 3.0), p, q, r);
  ASSERT_TRUE(crossing.has_value());
  EXPECT_NEAR(crossing->s, 0.25, 1e-15);
  EXPECT_TRUE(crossing->point.isApprox(Vec3(0.2, 0.3, 0.0), 1e-15));
  EXPECT_TRUE(crossing->normal.isApprox(Vec3::UnitZ(), 1e-15));
  // Either direction of the segment, either orientation of the triangle.
  EXPECT_TRUE(edge_triangle_crossing(Vec3(0.2, 0.3, 3.0), Vec3(0.2, 0.3, -1.0), p, r, q).has_value());
}

TEST(EdgeTriangleCrossing, ASegmentBesideOrShortOfTheTriangleDoesNotCross) {
  EXPECT_FALSE(edge_triangle_crossing(Vec3(0.8, 0.8, -1.0), Vec3(0.8, 0.8, 1.0), p, q, r).has_value());
  EXPECT_FALSE(edge_triangle_crossing(Vec3(0.2, 0.3, 0.5), Vec3(0.2, 0.3, 1.0), p, q, r).has_value());
}

TEST(EdgeTriangleCrossing, AnEndOnThePlaneOrASegmentInItIsNoCrossing) {
  EXPECT_FALSE(edge_triangle_crossing(Vec3(0.2, 0.3, 0.0), Vec3(0.2, 0.3, 1.0), p, q, r).has_value());
  EXPECT_FALSE(edge_triangle_crossing(Vec3(-1.0, 0.2, 0.0), Vec3(2.0, 0.2, 0.0), p, q, r).has_value());
}

TEST(EdgeTriangleCrossing, ThroughAnEdgeOrACornerCrosses) {
  // Through the side p-q, and through the corner q: the triangles beside either both count.
  EXPECT_TRUE(edge_triangle_crossing(Vec3(0.5, 0.0, -1.0), Vec3(0.5, 0.0, 1.0), p, q, r).has_value());
  EXPECT_TRUE(edge_triangle_crossing(Vec3(1.0, 0.0, -1.0), Vec3(1.0, 0.0, 1.0), p, q, r).has_value());
}

TEST(EdgeTriangleCrossing, ATriangleWithoutAreaIsCrossedByNothing) {
  EXPECT_FALSE(edge_triangle_crossing(Vec3(0.5, 0.0, -1.0), Vec3(0.5, 0.0, 1.0), p, q, Vec3(2.0, 0.0, 0.0))
                   .has_value());
}

}  // namespace
}  // namespace weft
