// The coplanarity cubic: coefficients against direct evaluation, near-coplanar intervals for
// simple, double and triple roots, degenerate (quadratic, linear, zero) cubics, the two early
// rejections (Bernstein bound, Lipschitz distance bound) and conservative advancement.
#include "collision/coplanarity_cubic.hpp"

#include <gtest/gtest.h>

#include "collision/point_triangle.hpp"

#include <random>

namespace weft {
namespace {

// A cubic with given coefficients and tolerance.
CoplanarityCubic cubic_of(double c0, double c1, double c2, double c3, double tolerance = 1e-12) {
  CoplanarityCubic cubic;
  cubic.coefficients = {c0, c1, c2, c3};
  cubic.tolerance = tolerance;
  return cubic;
}

bool covered(const std::array<TimeInterval, 3>& intervals, int count, double t) {
  for (int k = 0; k < count; ++k) {
    if (intervals[k].begin <= t && t <= intervals[k].end) return true;
  }
  return false;
}

TEST(CoplanarityCubic, CoefficientsMatchTheTripleProduct) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    Vec3 v[6];
    for (Vec3& x : v) x = Vec3(u(rng), u(rng), u(rng));
    const CoplanarityCubic cubic = coplanarity_cubic(v[0], v[1], v[2], v[3], v[4], v[5]);
    for (double t : {0.0, 0.3, 0.77, 1.0}) {
      const double direct = (v[0] + t * v[1]).cross(v[2] + t * v[3]).dot(v[4] + t * v[5]);
      EXPECT_NEAR(evaluate(cubic, t), direct, 1e-14);
    }
  }
}

TEST(CoplanarityCubic, ThreeSimpleRootsGiveThreeNarrowIntervals) {
  // (t - 0.2)(t - 0.5)(t - 0.9)
  const CoplanarityCubic cubic = cubic_of(-0.09, 0.73, -1.6, 1.0);
  std::array<TimeInterval, 3> intervals;
  const int count = near_coplanar_intervals(cubic, intervals);
  ASSERT_EQ(count, 3);
  const double roots[3] = {0.2, 0.5, 0.9};
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(intervals[k].begin, roots[k]);
    EXPECT_GE(intervals[k].end, roots[k]);
    EXPECT_LT(intervals[k].end - intervals[k].begin, 1e-9);
  }
}

TEST(CoplanarityCubic, DoubleAndTripleRootsWithoutSignChange) {
  std::array<TimeInterval, 3> intervals;
  // (t - 0.4)^2 (t + 1): touches zero at 0.4 without changing sign.
  const CoplanarityCubic touching = cubic_of(0.16, -0.64, 0.2, 1.0);
  int count = near_coplanar_intervals(touching, intervals);
  EXPECT_TRUE(covered(intervals, count, 0.4));
  // (t - 0.6)^3: triple root at the inflection.
  const CoplanarityCubic triple = cubic_of(-0.216, 1.08, -1.8, 1.0);
  count = near_coplanar_intervals(triple, intervals);
  EXPECT_TRUE(covered(intervals, count, 0.6));
  // A near miss that stays above the tolerance is not reported: (t - 0.4)^2 + 1e-6.
  const CoplanarityCubic above = cubic_of(0.16 + 1e-6, -0.8, 1.0, 0.0);
  EXPECT_EQ(near_coplanar_intervals(above, intervals), 0);
}

TEST(CoplanarityCubic, DegenerateCubics) {
  std::array<TimeInterval, 3> intervals;
  // Quadratic (t - 0.3)(t - 0.8), linear 0.5 - t, constant and identically zero.
  int count = near_coplanar_intervals(cubic_of(0.24, -1.1, 1.0, 0.0), intervals);
  ASSERT_EQ(count, 2);
  EXPECT_TRUE(covered(intervals, count, 0.3));
  EXPECT_TRUE(covered(intervals, count, 0.8));
  count = near_coplanar_intervals(cubic_of(0.5, -1.0, 0.0, 0.0), intervals);
  ASSERT_EQ(count, 1);
  EXPECT_TRUE(covered(intervals, count, 0.5));
  EXPECT_EQ(near_coplanar_intervals(cubic_of(2.0, 0.0, 0.0, 0.0), intervals), 0);
  count = near_coplanar_intervals(cubic_of(0.0, 0.0, 0.0, 0.0), intervals);
  ASSERT_EQ(count, 1);
  EXPECT_EQ(intervals[0].begin, 0.0);
  EXPECT_EQ(intervals[0].end, 1.0);
  // Roots exactly at the ends of the step: t (t - 1).
  count = near_coplanar_intervals(cubic_of(0.0, -1.0, 1.0, 0.0), intervals);
  EXPECT_TRUE(covered(intervals, count, 0.0));
  EXPECT_TRUE(covered(intervals, count, 1.0));
}

TEST(CoplanarityCubic, RandomCubicsHaveEverySampledSignChangeCovered) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int roots_checked = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    // Roots placed in or near [0, 1] (some nearly double), random scale.
    const double r0 = u(rng), r1 = trial % 2 ? r0 + 1e-7 * u(rng) : u(rng), r2 = 0.5 + u(rng);
    const double scale = std::pow(10.0, 3 * u(rng));
    // About one sampled sign change per trial on average: r0, r1 and r2 each fall in [0, 1]
    // half the time, but a near-double pair (odd trials) shows no sign change between samples.
    const CoplanarityCubic cubic = cubic_of(-scale * r0 * r1 * r2, scale * (r0 * r1 + r0 * r2 + r1 * r2),
                                            -scale * (r0 + r1 + r2), scale, 1e-12 * scale);
    std::array<TimeInterval, 3> intervals;
    const int count = near_coplanar_intervals(cubic, intervals);
    constexpr int samples = 4000;
    for (int i = 0; i < samples; ++i) {
      const double t0 = double(i) / samples, t1 = double(i + 1) / samples;
      if ((evaluate(cubic, t0) < 0.0) != (evaluate(cubic, t1) < 0.0)) {
        ++roots_checked;
        // Some time of the sample interval must be covered.
        bool hit = false;
        for (int k = 0; k < count; ++k) hit = hit || (intervals[k].begin <= t1 && intervals[k].end >= t0);
        ASSERT_TRUE(hit) << trial << " " << t0;
      }
    }
  }
  EXPECT_GT(roots_checked, 4500);
}

TEST(CoplanarityCubic, MayVanishRejectsOnlyCubicsBeyondTheToleranceAllOverTheStep) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int rejected = 0, kept_with_root = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    // Roots anywhere in [-1.5, 2.5]: about half the cubics have none in [0, 1].
    const double r0 = 0.5 + 2.0 * u(rng), r1 = 0.5 + 2.0 * u(rng), r2 = 0.5 + 2.0 * u(rng);
    const double scale = std::pow(10.0, 3 * u(rng));
    const CoplanarityCubic cubic = cubic_of(-scale * r0 * r1 * r2, scale * (r0 * r1 + r0 * r2 + r1 * r2),
                                            -scale * (r0 + r1 + r2), scale, 1e-12 * scale);
    double smallest = std::abs(evaluate(cubic, 0.0));
    for (int i = 1; i <= 4000; ++i) smallest = std::min(smallest, std::abs(evaluate(cubic, i / 4000.0)));
    const bool root_in_step = (r0 >= 0.0 && r0 <= 1.0) || (r1 >= 0.0 && r1 <= 1.0) || (r2 >= 0.0 && r2 <= 1.0);
    if (!may_vanish(cubic)) {
      ++rejected;
      ASSERT_FALSE(root_in_step) << trial;
      ASSERT_GT(smallest, cubic.tolerance) << trial;
      std::array<TimeInterval, 3> intervals;
      EXPECT_EQ(near_coplanar_intervals(cubic, intervals), 0);
    } else if (root_in_step) {
      ++kept_with_root;
    }
  }
  // It must settle a good share of the cubics without a root (else it is no filter) and keep
  // every one with a root.
  EXPECT_GT(rejected, 1000);
  EXPECT_GT(kept_with_root, 2000);
}

TEST(ConservativeAdvancement, MayComeWithinKeepsEveryVertexTrianglePairThatComesClose) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random_point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  const double eta = 0.05;
  int close = 0, rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 p = random_point(), a = random_point(), b = random_point(), c = random_point();
    const Vec3 dp = 0.5 * random_point(), da = 0.5 * random_point(), db = 0.5 * random_point(),
               dc = 0.5 * random_point();
    const auto distance_at = [&](double t) {
      return point_triangle_closest(p + t * dp, a + t * da, b + t * db, c + t * dc).distance;
    };
    const double lipschitz = std::max({(dp - da).norm(), (dp - db).norm(), (dp - dc).norm()});
    double smallest = distance_at(0.0);
    for (int i = 1; i <= 1000; ++i) smallest = std::min(smallest, distance_at(i / 1000.0));
    const bool kept = may_come_within(distance_at(0.0), distance_at(1.0), lipschitz, eta);
    if (smallest <= eta) {
      ++close;
      ASSERT_TRUE(kept) << trial;
    }
    if (!kept) ++rejected;
  }
  EXPECT_GT(close, 100);
  EXPECT_GT(rejected, 1000);
  // The bound is tight: a point passing straight through at the largest speed.
  EXPECT_TRUE(may_come_within(0.5, 0.5, 1.0, 0.0));
  EXPECT_FALSE(may_come_within(0.5, 0.5, 0.9, 0.0));
}

TEST(ConservativeAdvancement, FindsTheFirstTimeWithinEtaAndNothingWhenNone) {
  // A point moving at unit speed along x past the origin at height 0.1: |(t - 0.5, 0.1)|.
  const auto distance = [](double t) { return std::hypot(t - 0.5, 0.1); };
  const double hit = earliest_proximity(distance, {0.0, 1.0}, 0.2, 1.0, 1000);
  EXPECT_NEAR(hit, 0.5 - std::sqrt(0.2 * 0.2 - 0.1 * 0.1), 1e-6);
  EXPECT_LE(distance(hit), 0.2);
  EXPECT_LT(earliest_proximity(distance, {0.0, 1.0}, 0.05, 1.0, 1000), 0.0);
  // No motion: only the start is looked at.
  EXPECT_LT(earliest_proximity([](double) { return 1.0; }, {0.0, 1.0}, 0.5, 0.0), 0.0);
}

}  // namespace
}  // namespace weft
