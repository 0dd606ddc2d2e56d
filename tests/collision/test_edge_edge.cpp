// Closest points of two segments: crossing, skew, parallel (overlapping or not), zero-length,
// and random segments against dense sampling; edge_edge_offset against them.
#include "collision/edge_edge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace weft {
namespace {

void expect_consistent(const EdgeEdgeClosest& r, const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  EXPECT_GE(r.s, 0.0);
  EXPECT_LE(r.s, 1.0);
  EXPECT_GE(r.t, 0.0);
  EXPECT_LE(r.t, 1.0);
  EXPECT_LT((a0 + r.s * (a1 - a0) - r.point_a).norm(), 1e-12);
  EXPECT_LT((b0 + r.t * (b1 - b0) - r.point_b).norm(), 1e-12);
  EXPECT_NEAR(r.distance, (r.point_a - r.point_b).norm(), 1e-14);
}

TEST(EdgeEdge, SkewEdgesMeetInTheirInteriors) {
  const Vec3 a0(-1, 0, 0), a1(1, 0, 0), b0(0.5, -1, 0.2), b1(0.5, 1, 0.2);
  const EdgeEdgeClosest r = edge_edge_closest(a0, a1, b0, b1);
  EXPECT_NEAR(r.s, 0.75, 1e-14);
  EXPECT_NEAR(r.t, 0.5, 1e-14);
  EXPECT_NEAR(r.distance, 0.2, 1e-14);
  expect_consistent(r, a0, a1, b0, b1);
  const EdgeEdgeClosest crossing = edge_edge_closest(a0, a1, Vec3(0, -1, 0), Vec3(0, 1, 0));
  EXPECT_NEAR(crossing.distance, 0.0, 1e-15);
}

TEST(EdgeEdge, ClampedEndpoint) {
  const Vec3 a0(0, 0, 0), a1(1, 0, 0), b0(2, -1, 1), b1(2, 1, 1);
  const EdgeEdgeClosest r = edge_edge_closest(a0, a1, b0, b1);
  EXPECT_DOUBLE_EQ(r.s, 1.0);
  EXPECT_NEAR(r.t, 0.5, 1e-14);
  EXPECT_NEAR(r.distance, std::sqrt(2.0), 1e-14);
}

TEST(EdgeEdge, ParallelOverlappingAndDisjoint) {
  const Vec3 a0(0, 0, 0), a1(2, 0, 0);
  const EdgeEdgeClosest overlap = edge_edge_closest(a0, a1, Vec3(1, 0.5, 0), Vec3(3, 0.5, 0));
  EXPECT_NEAR(overlap.distance, 0.5, 1e-14);
  expect_consistent(overlap, a0, a1, Vec3(1, 0.5, 0), Vec3(3, 0.5, 0));
  const EdgeEdgeClosest apart = edge_edge_closest(a0, a1, Vec3(5, 0, 0), Vec3(3, 0, 0));
  EXPECT_NEAR(apart.distance, 1.0, 1e-14);
  EXPECT_DOUBLE_EQ(apart.s, 1.0);
  EXPECT_DOUBLE_EQ(apart.t, 1.0);
  // Collinear and overlapping: distance zero.
  EXPECT_NEAR(edge_edge_closest(a0, a1, Vec3(1, 0, 0), Vec3(4, 0, 0)).distance, 0.0, 1e-15);
  // Almost parallel (angle 1e-12): no blow-up.
  const EdgeEdgeClosest almost = edge_edge_closest(a0, a1, Vec3(0, 1, 0), Vec3(2, 1 + 2e-12, 0));
  EXPECT_NEAR(almost.distance, 1.0, 1e-11);
  expect_consistent(almost, a0, a1, Vec3(0, 1, 0), Vec3(2, 1 + 2e-12, 0));
}

TEST(EdgeEdge, ZeroLengthEdges) {
  const Vec3 p(0.5, 1, 0);
  const EdgeEdgeClosest point_edge = edge_edge_closest(p, p, Vec3(0, 0, 0), Vec3(1, 0, 0));
  EXPECT_NEAR(point_edge.distance, 1.0, 1e-14);
  EXPECT_NEAR(point_edge.t, 0.5, 1e-14);
  const EdgeEdgeClosest edge_point = edge_edge_closest(Vec3(0, 0, 0), Vec3(1, 0, 0), p, p);
  EXPECT_NEAR(edge_point.s, 0.5, 1e-14);
  const EdgeEdgeClosest points = edge_edge_closest(p, p, Vec3(0.5, 3, 0), Vec3(0.5, 3, 0));
  EXPECT_NEAR(points.distance, 2.0, 1e-14);
}

TEST(EdgeEdge, RandomSegmentsNeverBeatenByDenseSampling) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int samples = 200;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 a0(u(rng), u(rng), u(rng)), a1(u(rng), u(rng), u(rng));
    Vec3 b0(u(rng), u(rng), u(rng)), b1(u(rng), u(rng), u(rng));
    if (trial % 3 == 1) b1 = b0 + (a1 - a0) * 0.7 + 1e-10 * Vec3(u(rng), u(rng), u(rng));  // near parallel
    if (trial % 3 == 2) b1 = b0;                                                           // zero length
    const EdgeEdgeClosest r = edge_edge_closest(a0, a1, b0, b1);
    expect_consistent(r, a0, a1, b0, b1);
    // Brute force: for each sample on a, the exact closest point on b.
    double best = 1e300;
    for (int i = 0; i <= samples; ++i) {
      const Vec3 pa = a0 + (double(i) / samples) * (a1 - a0);
      const Vec3 e = b1 - b0;
      const double t = e.squaredNorm() > 0 ? std::clamp((pa - b0).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
      best = std::min(best, (pa - (b0 + t * e)).norm());
    }
    ASSERT_LE(r.distance, best + 1e-12) << trial;
    ASSERT_GE(r.distance, best - (a1 - a0).norm() / samples) << trial;
    // The cheap offset joins a point of each segment, so it is never shorter than the closest
    // pair, and it is that pair wherever the segments are clearly not parallel.
    const double offset = edge_edge_offset(a0, a1, b0, b1).norm();
    ASSERT_GE(offset, r.distance - 1e-12) << trial;
    if (trial % 3 == 0) {
      ASSERT_NEAR(offset, r.distance, 1e-12) << trial;
    }
  }
}

}  // namespace
}  // namespace weft
