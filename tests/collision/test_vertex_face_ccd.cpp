// Continuous vertex-face detection: hand-built degenerate cases and random cases (with many near
// misses) against a brute-force root finder.
#include "collision/vertex_face_ccd.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "collision/point_triangle.hpp"

namespace weft {
namespace {

constexpr double eta = 1e-6;

// Unit right triangle in z = 0, at rest unless moved.
const Vec3 a0(0, 0, 0), b0(1, 0, 0), c0(0, 1, 0);

std::optional<VertexFaceImpact> static_triangle(const Vec3& p_start, const Vec3& p_end, double tolerance = eta) {
  return vertex_face_ccd(p_start, a0, b0, c0, p_end, a0, b0, c0, tolerance);
}

TEST(VertexFaceCcd, VertexFallingThroughTheFaceHitsAtTheCrossing) {
  const auto hit = static_triangle(Vec3(0.2, 0.3, 1.0), Vec3(0.2, 0.3, -3.0));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.25, 1e-9);
  EXPECT_TRUE(hit->barycentric.isApprox(Vec3(0.5, 0.2, 0.3), 1e-6));
  EXPECT_TRUE(hit->normal.isApprox(Vec3::UnitZ(), 1e-12));  // towards the side it came from
  EXPECT_LE(hit->distance, eta);
}

TEST(VertexFaceCcd, BackFaceApproachCounts) {
  const auto hit = static_triangle(Vec3(0.2, 0.3, -1.0), Vec3(0.2, 0.3, 1.0));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.5, 1e-9);
  EXPECT_TRUE(hit->normal.isApprox(-Vec3::UnitZ(), 1e-12));
}

TEST(VertexFaceCcd, PassingBesideTheTriangleMisses) {
  EXPECT_FALSE(static_triangle(Vec3(0.6, 0.6, 1.0), Vec3(0.6, 0.6, -1.0)));  // beyond the hypotenuse
  EXPECT_FALSE(static_triangle(Vec3(0.2, 0.3, 1.0), Vec3(0.2, 0.3, 0.001)));  // stops short
}

TEST(VertexFaceCcd, ThroughAnEdgeAndThroughACornerExactly) {
  const auto edge = static_triangle(Vec3(0.5, 0.5, 1.0), Vec3(0.5, 0.5, -1.0));
  ASSERT_TRUE(edge);
  EXPECT_NEAR(edge->time, 0.5, 1e-9);
  EXPECT_NEAR(edge->barycentric[0], 0.0, 1e-9);
  const auto corner = static_triangle(Vec3(1, 0, 0.5), Vec3(1, 0, -0.5));
  ASSERT_TRUE(corner);
  EXPECT_NEAR(corner->time, 0.5, 1e-9);
  EXPECT_NEAR(corner->barycentric[1], 1.0, 1e-9);
  // Diagonal motion through the corner (not along the normal).
  const auto oblique = static_triangle(Vec3(0.0, -1.0, 0.5), Vec3(2, 1.0, -0.5));
  ASSERT_TRUE(oblique);
  EXPECT_NEAR(oblique->time, 0.5, 1e-9);
}

TEST(VertexFaceCcd, ZeroMotion) {
  EXPECT_FALSE(static_triangle(Vec3(0.2, 0.2, 0.1), Vec3(0.2, 0.2, 0.1)));
  // Resting on the face: in contact from the start.
  const auto resting = static_triangle(Vec3(0.2, 0.2, 0.0), Vec3(0.2, 0.2, 0.0));
  ASSERT_TRUE(resting);
  EXPECT_EQ(resting->time, 0.0);
}

TEST(VertexFaceCcd, TouchingAtTheStartAndAtTheEnd) {
  const auto start = static_triangle(Vec3(0.2, 0.2, 0.0), Vec3(0.2, 0.2, 1.0));
  ASSERT_TRUE(start);
  EXPECT_EQ(start->time, 0.0);
  const auto end = static_triangle(Vec3(0.2, 0.2, 1.0), Vec3(0.2, 0.2, 0.0));
  ASSERT_TRUE(end);
  EXPECT_NEAR(end->time, 1.0, 1e-9);
  EXPECT_TRUE(end->normal.isApprox(Vec3::UnitZ(), 1e-12));
}

TEST(VertexFaceCcd, CoplanarMotionEntersThroughAnEdge) {
  // Sliding in the triangle's plane from outside, across the edge x = 0 at t = 0.5.
  const auto hit = static_triangle(Vec3(-0.5, 0.25, 0.0), Vec3(0.5, 0.25, 0.0));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.5, 1e-5);
  EXPECT_NEAR(hit->normal.norm(), 1.0, 1e-12);
  // In the plane but passing by.
  EXPECT_FALSE(static_triangle(Vec3(-0.5, 1.5, 0.0), Vec3(1.5, 1.5, 0.0)));
  // The whole configuration moving together in its plane: never closer.
  const Vec3 shift(0.3, -0.2, 0.0);
  EXPECT_FALSE(vertex_face_ccd(Vec3(0.8, 0.8, 0), a0, b0, c0, Vec3(0.8, 0.8, 0) + shift, a0 + shift, b0 + shift,
                               c0 + shift, eta));
}

TEST(VertexFaceCcd, TriangleSweepsOverAStillVertexAndRotatingTriangle) {
  // The triangle moves down through a vertex at rest.
  const Vec3 p(0.25, 0.25, 0.0);
  const Vec3 up(0, 0, 1), down(0, 0, -1);
  const auto hit = vertex_face_ccd(p, a0 + up, b0 + up, c0 + up, p, a0 + down, b0 + down, c0 + down, eta);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->time, 0.5, 1e-9);
  EXPECT_TRUE(hit->normal.isApprox(-Vec3::UnitZ(), 1e-12));  // the vertex is below, relative to the face
  // A corner of the triangle swings through the vertex (non-linear f: a genuine cubic).
  const auto swing = vertex_face_ccd(Vec3(0.9, 0.05, 0.0), a0, Vec3(1, 0, 1), c0, Vec3(0.9, 0.05, 0.0), a0,
                                     Vec3(1, 0, -1), c0, eta);
  ASSERT_TRUE(swing);
  EXPECT_NEAR(swing->time, 0.5, 1e-6);
}

TEST(VertexFaceCcd, DegenerateTriangles) {
  // A needle (collinear corners) that the vertex passes through.
  const Vec3 n0(0, 0, 0), n1(2, 0, 0), n2(1, 0, 0);
  const auto needle = vertex_face_ccd(Vec3(0.5, 1, 0), n0, n1, n2, Vec3(0.5, -1, 0), n0, n1, n2, eta);
  ASSERT_TRUE(needle);
  EXPECT_NEAR(needle->time, 0.5, 1e-5);
  EXPECT_NEAR(needle->normal.norm(), 1.0, 1e-12);
  // A triangle collapsed to a point that the vertex passes exactly through.
  const Vec3 q(0.1, 0.2, 0.3);
  const auto point = vertex_face_ccd(Vec3(0.1, 0.2, -0.7), q, q, q, Vec3(0.1, 0.2, 1.3), q, q, q, eta);
  ASSERT_TRUE(point);
  EXPECT_NEAR(point->time, 0.5, 1e-5);
  EXPECT_FALSE(vertex_face_ccd(Vec3(0.1, 0.3, -0.7), q, q, q, Vec3(0.1, 0.3, 1.3), q, q, q, eta));
}

// Brute force: f sampled densely from the interpolated positions, bisection on every sign change
// (and exact zeros), then the same proximity check; the earliest accepted root.
std::optional<double> brute_force(const Vec3 (&x0)[4], const Vec3 (&x1)[4], double tolerance) {
  const auto at = [&](int k, double t) { return Vec3((1 - t) * x0[k] + t * x1[k]); };
  const auto f = [&](double t) {
    return (at(2, t) - at(1, t)).cross(at(3, t) - at(1, t)).dot(at(0, t) - at(1, t));
  };
  const auto accepted = [&](double t) {
    return point_triangle_closest(at(0, t), at(1, t), at(2, t), at(3, t)).distance <= tolerance;
  };
  constexpr int samples = 1000;
  double f_lo = f(0.0);
  for (int i = 0; i < samples; ++i) {
    double lo = double(i) / samples, hi = double(i + 1) / samples;
    const double f_hi = f(hi);
    if (f_lo == 0.0 && accepted(lo)) return lo;
    if ((f_lo < 0.0) != (f_hi < 0.0) && f_hi != 0.0) {
      const bool low_negative = f_lo < 0.0;
      for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo + hi);
        ((f(mid) < 0.0) == low_negative ? lo : hi) = mid;
      }
      if (accepted(lo)) return lo;
      if (accepted(hi)) return hi;
    }
    f_lo = f_hi;
  }
  if (f_lo == 0.0 && accepted(1.0)) return 1.0;
  return std::nullopt;
}

TEST(VertexFaceCcd, RandomCasesMissNothingTheBruteForceFinds) {
  std::mt19937 rng(2002);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr double tolerance = 1e-3;
  int brute_hits = 0, ccd_hits = 0, extra = 0, near_misses = 0;
  constexpr int cases = 20000;
  for (int trial = 0; trial < cases; ++trial) {
    Vec3 x0[4], x1[4];
    for (int k = 1; k < 4; ++k) {
      x0[k] = Vec3(u(rng), u(rng), u(rng));
      x1[k] = x0[k] + 0.7 * Vec3(u(rng), u(rng), u(rng));
    }
    if (trial % 5 == 4) {  // needle triangle
      x0[3] = x0[1] + 0.4 * (x0[2] - x0[1]) + 1e-7 * Vec3(u(rng), u(rng), u(rng));
      x1[3] = x1[1] + 0.4 * (x1[2] - x1[1]);
    }
    x0[0] = Vec3(u(rng), u(rng), u(rng));
    if (trial % 4 == 0) {
      x1[0] = x0[0] + Vec3(u(rng), u(rng), u(rng));
    } else {
      // Aim the vertex at a point near the triangle at time t*: barycentrics a little outside
      // or exactly on an edge, offset off the plane by up to twice the tolerance.
      const double t_star = 0.02 + 0.98 * unit(rng);
      Vec3 w(1.1 * unit(rng) - 0.05, 1.1 * unit(rng) - 0.05, 0.0);
      if (trial % 4 == 2) w[0] = 0.0;
      w[2] = 1.0 - w[0] - w[1];
      Vec3 xt[4];
      for (int k = 1; k < 4; ++k) xt[k] = (1 - t_star) * x0[k] + t_star * x1[k];
      Vec3 normal = (xt[2] - xt[1]).cross(xt[3] - xt[1]);
      if (normal.norm() > 0) normal.normalize();
      const double offset = trial % 4 == 3 ? 2.0 * tolerance * u(rng) : 0.0;
      const Vec3 target = w[0] * xt[1] + w[1] * xt[2] + w[2] * xt[3] + offset * normal;
      x1[0] = x0[0] + (target - x0[0]) / t_star;
      ++near_misses;
    }
    const std::optional<double> expected = brute_force(x0, x1, tolerance);
    const auto hit = vertex_face_ccd(x0[0], x0[1], x0[2], x0[3], x1[0], x1[1], x1[2], x1[3], tolerance);
    if (expected) {
      ++brute_hits;
      ASSERT_TRUE(hit) << "missed collision in case " << trial << " at t = " << *expected;
      ASSERT_LE(hit->time, *expected + 1e-9) << trial;
    }
    if (hit) {
      ++ccd_hits;
      ASSERT_LE(hit->distance, tolerance * (1 + 1e-9)) << trial;
      ASSERT_NEAR(hit->normal.norm(), 1.0, 1e-9) << trial;
      ASSERT_NEAR(hit->barycentric.sum(), 1.0, 1e-9) << trial;
      if (!expected) ++extra;
    }
  }
  std::cout << "vertex-face CCD: " << cases << " cases (" << near_misses << " aimed), brute force " << brute_hits
            << " hits, CCD " << ccd_hits << " (" << extra << " beyond the brute force)\n";
  EXPECT_GT(brute_hits, cases / 4);
  EXPECT_LT(extra, cases / 100);
}

}  // namespace
}  // namespace weft
