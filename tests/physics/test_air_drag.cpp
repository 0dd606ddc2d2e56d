// Air drag: no force for tangential motion without tangential drag, opposition to motion through
// the triangle, wind as a moving frame, and the velocity Jacobian against finite differences.
#include "physics/air_drag.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

namespace weft {
namespace {

// A triangle in the plane z = 0.5 with normal +z and area 1.
const Vec3 x0(0.0, 0.0, 0.5), x1(2.0, 0.0, 0.5), x2(0.5, 1.0, 0.5);

Vector9d drag(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& wind, double normal_coefficient,
              double tangential_coefficient, Matrix9d* jacobian = nullptr) {
  Vector9d force;
  air_drag_forces(x0, x1, x2, v0, v1, v2, wind, normal_coefficient, tangential_coefficient, force, jacobian);
  return force;
}

TEST(AirDrag, TangentialMotionIsFreeWithoutTangentialDrag) {
  const Vec3 v(1.0, -2.0, 0.0);
  EXPECT_LE(drag(v, v, v, Vec3::Zero(), 3.0, 0.0).norm(), 1e-15);
  // With a tangential coefficient it is resisted along the motion, per vertex -(ct A/3) u.
  const Vector9d force = drag(v, v, v, Vec3::Zero(), 3.0, 0.3);
  for (int i = 0; i < 3; ++i) EXPECT_LE((force.segment<3>(3 * i) + 0.1 * v).norm(), 1e-15);
}

TEST(AirDrag, OpposesMotionThroughTheTriangle) {
  // Average velocity (0, 0, 2) (vertex velocities differ): f = -(cn A/3)(u.n) n on each vertex.
  const Vector9d force = drag(Vec3(1, 0, 1), Vec3(-1, 0, 2), Vec3(0, 0, 3), Vec3::Zero(), 1.5, 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_LE((force.segment<3>(3 * i) - Vec3(0, 0, -1.0)).norm(), 1e-15);
  // Flipping the triangle's orientation does not change the force.
  Vector9d flipped;
  air_drag_forces(x0, x2, x1, Vec3(1, 0, 1), Vec3(-1, 0, 2), Vec3(0, 0, 3), Vec3::Zero(), 1.5, 0.0, flipped,
                  nullptr);
  EXPECT_LE((flipped - force).norm(), 1e-15);
}

TEST(AirDrag, WindIsRelativeMotion) {
  const Vec3 wind(0.3, -0.2, 4.0);
  EXPECT_LE(drag(wind, wind, wind, wind, 2.0, 0.5).norm(), 1e-15);
  // Still cloth in an upward wind is pushed up.
  const Vector9d force = drag(Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, 4), 2.0, 0.0);
  EXPECT_GT(force[2], 0.0);
}

TEST(AirDrag, VelocityJacobianMatchesFiniteDifferencesAndIsNegativeSemiDefinite) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal;
  Vector9d v;
  for (int i = 0; i < 9; ++i) v[i] = normal(rng);
  const Vec3 wind(0.5, 1.0, -0.3);
  const auto force_at = [&](const Vector9d& velocity, Matrix9d* jacobian) {
    return drag(velocity.segment<3>(0), velocity.segment<3>(3), velocity.segment<3>(6), wind, 1.2, 0.1, jacobian);
  };
  Matrix9d jacobian;
  force_at(v, &jacobian);
  const double h = 1e-6;
  for (int j = 0; j < 9; ++j) {
    Vector9d step = Vector9d::Zero();
    step[j] = h;
    const Vector9d column = (force_at(v + step, nullptr) - force_at(v - step, nullptr)) / (2.0 * h);
    EXPECT_LE((column - jacobian.col(j)).norm(), 1e-8) << "column " << j;
  }
  EXPECT_LE((jacobian - jacobian.transpose()).norm(), 1e-15);
  const Eigen::SelfAdjointEigenSolver<Matrix9d> eigen(jacobian);
  EXPECT_LE(eigen.eigenvalues().maxCoeff(), 1e-15);
}

TEST(AirDrag, ZeroAreaTriangleFeelsNoDrag) {
  Vector9d force;
  Matrix9d jacobian;
  air_drag_forces(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1),
                  Vec3::Zero(), 1.0, 1.0, force, &jacobian);
  EXPECT_EQ(force, Vector9d::Zero());
  EXPECT_EQ(jacobian, Matrix9d::Zero());
}

}  // namespace
}  // namespace weft
