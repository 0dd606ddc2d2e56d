// Closest point of a triangle: every Voronoi region, needle and zero-area triangles, and random
// triangles against dense sampling of the triangle.
#include "collision/point_triangle.hpp"

#include <gtest/gtest.h>

#include <random>

namespace weft {
namespace {

void expect_consistent(const PointTriangleClosest& r, const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  EXPECT_NEAR(r.barycentric.sum(), 1.0, 1e-12);
  EXPECT_GE(r.barycentric.minCoeff(), 0.0);
  EXPECT_TRUE((r.barycentric[0] * a + r.barycentric[1] * b + r.barycentric[2] * c).isApprox(r.closest, 1e-12) ||
              (r.closest - (r.barycentric[0] * a + r.barycentric[1] * b + r.barycentric[2] * c)).norm() < 1e-12);
  EXPECT_NEAR(r.distance, (p - r.closest).norm(), 1e-14);
}

TEST(PointTriangle, InteriorProjectsOntoThePlaneFromEitherSide) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  for (double side : {1.0, -1.0}) {
    const Vec3 p(0.25, 0.25, 0.3 * side);
    const PointTriangleClosest r = point_triangle_closest(p, a, b, c);
    EXPECT_NEAR(r.distance, 0.3, 1e-14);
    EXPECT_TRUE(r.barycentric.isApprox(Vec3(0.5, 0.25, 0.25), 1e-14));
    expect_consistent(r, p, a, b, c);
  }
}

TEST(PointTriangle, VertexAndEdgeRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const PointTriangleClosest corner = point_triangle_closest(Vec3(2, -1, 0.5), a, b, c);
  EXPECT_TRUE(corner.barycentric.isApprox(Vec3(0, 1, 0)));
  EXPECT_NEAR(corner.distance, std::sqrt(1 + 1 + 0.25), 1e-14);
  const PointTriangleClosest edge = point_triangle_closest(Vec3(0.5, -2, 0), a, b, c);
  EXPECT_TRUE(edge.barycentric.isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_NEAR(edge.distance, 2.0, 1e-14);
  const PointTriangleClosest hypotenuse = point_triangle_closest(Vec3(1, 1, 0), a, b, c);
  EXPECT_TRUE(hypotenuse.barycentric.isApprox(Vec3(0, 0.5, 0.5)));
  EXPECT_NEAR(hypotenuse.distance, std::sqrt(0.5), 1e-14);
}

TEST(PointTriangle, NeedleAndZeroAreaTriangles) {
  // Collinear corners: the triangle is the segment from (0,0,0) to (2,0,0).
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(1, 0, 0);
  const PointTriangleClosest needle = point_triangle_closest(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_NEAR(needle.distance, 1.0, 1e-14);
  EXPECT_TRUE(needle.closest.isApprox(Vec3(1.5, 0, 0)));
  expect_consistent(needle, Vec3(1.5, 1, 0), a, b, c);
  // Nearly collinear (area ~ 1e-15): still a finite, consistent answer.
  const PointTriangleClosest thin = point_triangle_closest(Vec3(1.5, 1, 0), a, b, Vec3(1, 1e-15, 0));
  EXPECT_NEAR(thin.distance, 1.0, 1e-12);
  expect_consistent(thin, Vec3(1.5, 1, 0), a, b, Vec3(1, 1e-15, 0));
  // All three corners at one point.
  const Vec3 q(1, 2, 3);
  const PointTriangleClosest point = point_triangle_closest(Vec3(1, 2, 4), q, q, q);
  EXPECT_NEAR(point.distance, 1.0, 1e-14);
  EXPECT_NEAR(point.barycentric.sum(), 1.0, 1e-14);
}

TEST(PointTriangle, RandomTrianglesNeverBeatenByDenseSampling) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int samples = 60;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng));
    Vec3 b(u(rng), u(rng), u(rng));
    Vec3 c(u(rng), u(rng), u(rng));
    if (trial % 4 == 1) c = a + 0.3 * (b - a) + 1e-9 * Vec3(u(rng), u(rng), u(rng));  // needle
    if (trial % 4 == 2) b = a;                                                          // segment
    const Vec3 p(2 * u(rng), 2 * u(rng), 2 * u(rng));
    const PointTriangleClosest r = point_triangle_closest(p, a, b, c);
    expect_consistent(r, p, a, b, c);
    double best = 1e300;
    for (int i = 0; i <= samples; ++i) {
      for (int j = 0; i + j <= samples; ++j) {
        const double wb = double(i) / samples, wc = double(j) / samples;
        best = std::min(best, (p - ((1 - wb - wc) * a + wb * b + wc * c)).norm());
      }
    }
    ASSERT_LE(r.distance, best + 1e-12) << trial;
    ASSERT_GE(r.distance, best - 0.05) << trial;  // sampling spacing bound
  }
}

TEST(PointSegment, ClampsAndHandlesZeroLength) {
  EXPECT_DOUBLE_EQ(point_segment_parameter(Vec3(-1, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)), 0.0);
  EXPECT_DOUBLE_EQ(point_segment_parameter(Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)), 0.5);
  EXPECT_DOUBLE_EQ(point_segment_parameter(Vec3(5, 1, 0), Vec3(0, 0, 0), Vec3(2, 0, 0)), 1.0);
  EXPECT_DOUBLE_EQ(point_segment_parameter(Vec3(5, 1, 0), Vec3(1, 1, 1), Vec3(1, 1, 1)), 0.0);
}

}  // namespace
}  // namespace weft
