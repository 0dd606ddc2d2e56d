// The scalar contact laws of the barrier response: derivatives against finite differences, the
// barrier's C2 end at the contact radius and its growth without bound at contact, and friction's
// smoothing joining Coulomb's constant force at eps.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/contact_barrier.hpp"

namespace weft {
namespace {

TEST(LogBarrier, DerivativesMatchFiniteDifferences) {
  const double dhat = 5e-3;
  for (const double d : {1e-4, 1e-3, 2.5e-3, 4.9e-3}) {
    const double step = 1e-7 * d;
    const BarrierValue b = log_barrier(d, dhat);
    const BarrierValue up = log_barrier(d + step, dhat), down = log_barrier(d - step, dhat);
    EXPECT_NEAR(b.first, (up.value - down.value) / (2 * step), 1e-6 * std::abs(b.first) + 1e-12) << d;
    EXPECT_NEAR(b.second, (up.first - down.first) / (2 * step), 1e-5 * std::abs(b.second) + 1e-9) << d;
    EXPECT_GT(b.value, 0.0);
    EXPECT_LT(b.first, 0.0);
    EXPECT_GT(b.second, 0.0);
  }
}

TEST(LogBarrier, EndsTwiceDifferentiablyAtTheRadiusAndGrowsWithoutBoundAtContact) {
  const double dhat = 5e-3;
  const BarrierValue beyond = log_barrier(dhat, dhat);
  EXPECT_EQ(beyond.value, 0.0);
  EXPECT_EQ(beyond.first, 0.0);
  EXPECT_EQ(beyond.second, 0.0);
  const BarrierValue near_end = log_barrier(dhat * (1 - 1e-6), dhat);
  EXPECT_LT(near_end.value, 1e-15);
  EXPECT_LT(std::abs(near_end.first), 1e-10);
  EXPECT_LT(near_end.second, 1e-4);
  // Towards contact the energy grows like -dhat^2 ln d and the force like dhat^2 / d.
  EXPECT_GT(log_barrier(1e-12, dhat).value, log_barrier(1e-6, dhat).value);
  EXPECT_GT(log_barrier(1e-300, dhat).value, 20.0 * log_barrier(1e-3, dhat).value);
  EXPECT_GT(-log_barrier(1e-9, dhat).first, 1e5 * -log_barrier(1e-3, dhat).first);
}

TEST(SmoothedFriction, DerivativesMatchFiniteDifferencesAndJoinCoulombAtEpsilon) {
  const double eps = 1e-4;
  for (const double y : {1e-6, 3e-5, 9e-5, 2e-4}) {
    const double step = 1e-7 * eps;
    const FrictionValue f = smoothed_friction(y, eps);
    const FrictionValue up = smoothed_friction(y + step, eps), down = smoothed_friction(y - step, eps);
    EXPECT_NEAR(f.first, (up.value - down.value) / (2 * step), 1e-6) << y;
    EXPECT_NEAR(f.second, (up.first - down.first) / (2 * step), 1e-6 / eps) << y;
    EXPECT_NEAR(f.ratio, f.first / y, 1e-9 / y) << y;
  }
  const FrictionValue below = smoothed_friction(eps * (1 - 1e-9), eps), above = smoothed_friction(eps, eps);
  EXPECT_NEAR(below.value, above.value, 1e-12);
  EXPECT_NEAR(below.first, 1.0, 1e-8);
  EXPECT_EQ(above.first, 1.0);
  EXPECT_EQ(smoothed_friction(0.0, eps).first, 0.0);  // at rest, no force
}

}  // namespace
}  // namespace weft
