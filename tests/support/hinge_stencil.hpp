#pragma once
// Test helpers for four-vertex hinge stencils (x0..x3 stacked in a 12-vector): random rotations and
// the checks every bending energy that rigid motion leaves unchanged must pass.
#include <gtest/gtest.h>

#include <random>

#include "core/math.hpp"

namespace weft::testing {

inline Vec3 stencil_vertex(const Vector12d& q, int i) { return q.segment<3>(3 * i); }

inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

// The forces (the gradient) on a stencil from an energy invariant under rigid motion sum to no net
// force and no net torque, to round-off.
inline void expect_no_net_force_or_torque(const Vector12d& q, const Vector12d& gradient) {
  Vec3 net_force = Vec3::Zero(), net_torque = Vec3::Zero();
  double scale = 0.0;
  for (int i = 0; i < 4; ++i) {
    net_force += gradient.segment<3>(3 * i);
    net_torque += stencil_vertex(q, i).cross(gradient.segment<3>(3 * i));
    scale += stencil_vertex(q, i).norm() * gradient.segment<3>(3 * i).norm();
  }
  EXPECT_LE(net_force.norm(), 1e-12 * gradient.norm());
  EXPECT_LE(net_torque.norm(), 1e-12 * scale);
}

// After a rigid motion (rotation, shift) of the stencil the energy is the same and the gradient is
// the rotated one; `energy_of(q, gradient)` evaluates the energy under test.
template <class Energy>
void expect_rigid_motion_invariance(const Vector12d& q, const Mat3& rotation, const Vec3& shift,
                                    const Energy& energy_of) {
  Vector12d gradient, moved, moved_gradient;
  const double energy = energy_of(q, &gradient);
  for (int i = 0; i < 4; ++i) moved.segment<3>(3 * i) = rotation * stencil_vertex(q, i) + shift;
  EXPECT_NEAR(energy_of(moved, &moved_gradient), energy, 1e-12 * energy);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LE((moved_gradient.segment<3>(3 * i) - rotation * gradient.segment<3>(3 * i)).norm(),
              1e-10 * gradient.norm());
  }
}

}  // namespace weft::testing
