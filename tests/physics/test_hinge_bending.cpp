// Hinge bending: the dihedral angle's value and sign convention, energy derivatives by Taylor
// tests (also across theta = +-pi), rigid-motion invariance with no net force or torque, and
// zero forces instead of NaN on degenerate triangles.
#include "physics/hinge_bending.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <vector>

#include "core/mesh_generators.hpp"
#include "core/topology.hpp"
#include "physics/psd_projection.hpp"
#include "physics/sparse_hessian.hpp"
#include "support/hinge_stencil.hpp"
#include "support/taylor.hpp"

namespace weft {
namespace {

using weft::testing::all_near_quarter;
using weft::testing::expect_no_net_force_or_torque;
using weft::testing::expect_rigid_motion_invariance;
using weft::testing::halving_ratios;
using weft::testing::random_rotation;

Vec3 at(const Vector12d& q, int i) { return weft::testing::stencil_vertex(q, i); }

double energy_of(const Vector12d& q, const HingeRest& rest, double stiffness, Vector12d* gradient = nullptr,
                 Matrix12d* hessian = nullptr) {
  return hinge_bending_energy(at(q, 0), at(q, 1), at(q, 2), at(q, 3), rest, stiffness, gradient, hessian);
}

double angle_of(const Vector12d& q) { return dihedral_angle(at(q, 0), at(q, 1), at(q, 2), at(q, 3)); }

HingeRest rest_of(const Vector12d& q) { return hinge_rest(at(q, 0), at(q, 1), at(q, 2), at(q, 3)); }

// Edge (0,0,0)-(1,0,0), x2 above it in the XY plane, x3 below it rotated by `fold` about +x
// (theta = fold without noise), each coordinate jittered by up to `noise`, then moved rigidly.
Vector12d folded_hinge(double fold, double noise, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-noise, noise);
  const Vec3 x3_flat(0.6, -0.8, 0.0);
  Vector12d q;
  q << 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.4, 0.9, 0.0,
      Eigen::AngleAxisd(fold, Vec3::UnitX()).toRotationMatrix() * x3_flat;
  for (int i = 0; i < 12; ++i) q[i] += jitter(rng);
  const Mat3 rotation = random_rotation(rng);
  const Vec3 shift = Vec3::Random();
  for (int i = 0; i < 4; ++i) q.segment<3>(3 * i) = rotation * at(q, i) + shift;
  return q;
}

Vector12d random_direction(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Vector12d d;
  for (int i = 0; i < 12; ++i) d[i] = normal(rng);
  return d;
}

void check_derivatives(const Vector12d& q, const HingeRest& rest, const Vector12d& direction) {
  const double stiffness = 0.7;
  Vector12d gradient;
  Matrix12d hessian;
  const double energy = energy_of(q, rest, stiffness, &gradient, &hessian);
  const auto energy_remainder = [&](double a) {
    return std::abs(energy_of(q + a * direction, rest, stiffness) - energy - a * gradient.dot(direction));
  };
  const auto gradient_remainder = [&](double a) {
    Vector12d moved;
    energy_of(q + a * direction, rest, stiffness, &moved);
    return (moved - gradient - a * hessian * direction).norm();
  };
  EXPECT_TRUE(all_near_quarter(halving_ratios(energy_remainder, 1e-3, 5))) << "theta " << angle_of(q);
  EXPECT_TRUE(all_near_quarter(halving_ratios(gradient_remainder, 1e-3, 5))) << "theta " << angle_of(q);
  EXPECT_LE((hessian - hessian.transpose()).norm(), 1e-10 * hessian.norm());

  Matrix12d projected = hessian;
  project_to_psd(projected);
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eigen(projected);
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * eigen.eigenvalues().maxCoeff());
}

TEST(HingeBending, DerivativesTaylorTest) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> fold(-2.5, 2.5);
  std::uniform_real_distribution<double> rest_angle(-0.6, 0.6);
  for (int trial = 0; trial < 12; ++trial) {
    const Vector12d q = folded_hinge(fold(rng), 0.15, rng);
    HingeRest rest = rest_of(folded_hinge(0.0, 0.15, rng));
    rest.rest_angle = rest_angle(rng);
    if (std::abs(angle_of(q) - rest.rest_angle) > 2.9) continue;  // keep clear of the wrap jump
    check_derivatives(q, rest, random_direction(rng));
  }
}

TEST(HingeBending, DerivativesTaylorTestAcrossThetaPi) {
  // Folded flat (theta just below pi) with a rest angle just past -pi: Taylor steps cross pi,
  // where the wrapped angle difference keeps the energy smooth.
  std::mt19937 rng(6);
  for (int trial = 0; trial < 4; ++trial) {
    const Vector12d q = folded_hinge(pi - 1e-4, 0.0, rng);
    HingeRest rest = rest_of(folded_hinge(0.0, 0.1, rng));
    rest.rest_angle = -pi + 0.01;
    EXPECT_NEAR(angle_of(q), pi - 1e-4, 1e-9);
    check_derivatives(q, rest, random_direction(rng));
  }
}

TEST(HingeBending, FactoredGaussNewtonFormMatchesTheElementMatrix) {
  // hinge_bending_gauss_newton gives the energy and gradient of hinge_bending_energy and the
  // Gauss-Newton Hessian 2k a a^T as curvature * a a^T; with E = k d^2 and g = 2k d a that
  // matrix is g g^T / (2E), formed here from hinge_bending_energy's (Taylor-tested) energy and
  // gradient. Assembled with add_element_outer it fills the same matrix as the formed 12x12
  // element, and with the wing tips left out of the pattern it puts 2 curvature a_p a_p^T on
  // their diagonal blocks.
  std::mt19937 rng(23);
  const double stiffness = 0.7;
  const Vector12d rest_shape = folded_hinge(0.3, 0.05, rng);
  Eigen::Matrix<int, 4, 1> hinge(0, 1, 2, 3);
  for (const double fold : {-2.0, -0.4, 0.0, 1.1, 3.0}) {
    const Vector12d q = folded_hinge(fold, 0.05, rng);
    Vector12d gradient;
    const double energy = hinge_bending_energy(at(q, 0), at(q, 1), at(q, 2), at(q, 3), rest_of(rest_shape), stiffness,
                                               &gradient, nullptr);
    ASSERT_GT(energy, 0.0);
    const Matrix12d gauss_newton = gradient * gradient.transpose() / (2.0 * energy);
    const HingeGaussNewton factored =
        hinge_bending_gauss_newton(at(q, 0), at(q, 1), at(q, 2), at(q, 3), rest_of(rest_shape), stiffness);
    EXPECT_EQ(factored.energy, energy);
    EXPECT_LE((factored.gradient - gradient).norm(), 1e-15 * gradient.norm());
    const Matrix12d outer = factored.curvature * factored.angle_gradient * factored.angle_gradient.transpose();
    EXPECT_LE((outer - gauss_newton).norm(), 1e-14 * gauss_newton.norm());
    ASSERT_GT(gauss_newton.norm(), 0.0);

    SparseHessian formed, unformed;
    int stencil = 0;
    for (SparseHessian* h : {&formed, &unformed}) {
      h->begin_pattern(4);
      stencil = h->add_stencil<4>(hinge);
      h->finish_pattern();
      h->set_zero();
    }
    formed.add_element<4>(stencil, 0, gauss_newton);
    unformed.add_element_outer<4>(stencil, 0, factored.curvature, factored.angle_gradient);
    const Eigen::MatrixXd a = Eigen::MatrixXd(formed.matrix()), b = Eigen::MatrixXd(unformed.matrix());
    EXPECT_LE((a - b).norm(), 1e-14 * a.norm());
    EXPECT_GT(b.block(6, 9, 3, 3).norm(), 0.0);  // the wing tips are coupled
  }
}

TEST(HingeBending, AngleIsZeroFlatAndSignedNinetyDegreesFolded) {
  const Vec3 x0(0, 0, 0), x1(1, 0, 0), x2(0.5, 1, 0);  // normal +z
  EXPECT_NEAR(dihedral_angle(x0, x1, x2, Vec3(0.3, -1, 0)), 0.0, 1e-15);
  // Wing folded away from the front (below the +z side): convex, a mountain.
  EXPECT_NEAR(dihedral_angle(x0, x1, x2, Vec3(0.5, 0, -1)), pi / 2, 1e-15);
  // Wing folded towards the front: concave, a valley.
  EXPECT_NEAR(dihedral_angle(x0, x1, x2, Vec3(0.5, 0, 1)), -pi / 2, 1e-15);
  // Swapping the triangles (the same hinge seen from the other edge direction) keeps the angle.
  EXPECT_NEAR(dihedral_angle(x1, x0, Vec3(0.5, 0, -1), x2), pi / 2, 1e-15);
}

TEST(HingeBending, EveryEdgeOfAnOutwardBoxIsConvex) {
  const TriangleMesh box = make_box(Vec3(0.5, 0.7, 0.9));
  const MeshTopology topology = build_topology(box.triangles, box.num_vertices());
  ASSERT_EQ(topology.num_hinges(), 18);
  int right_angles = 0;
  for (int h = 0; h < topology.num_hinges(); ++h) {
    const auto x = [&](int k) { return Vec3(box.positions.col(topology.hinges(k, h))); };
    const double theta = dihedral_angle(x(0), x(1), x(2), x(3));
    if (std::abs(theta) > 1e-12) {
      EXPECT_NEAR(theta, pi / 2, 1e-12);
      ++right_angles;
    }
  }
  EXPECT_EQ(right_angles, 12);  // the 6 face diagonals are flat
}

TEST(HingeBending, RestWeightIsThreeEdgeSquaredOverAreas) {
  const Vec3 x0(0, 0, 0), x1(2, 0, 0), x2(0.5, 1, 0), x3(1, -3, 0);
  const HingeRest rest = hinge_rest(x0, x1, x2, x3);
  EXPECT_NEAR(rest.rest_angle, 0.0, 1e-15);
  EXPECT_NEAR(rest.weight, 3.0 * 4.0 / (1.0 + 3.0), 1e-14);
  EXPECT_NEAR(hinge_bending_energy(x0, x1, x2, x3, rest, 2.0, nullptr, nullptr), 0.0, 1e-30);
}

TEST(HingeBending, RigidMotionInvariantWithoutNetForceOrTorque) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> fold(-3.0, 3.0);
  const double stiffness = 1.3;
  for (int trial = 0; trial < 10; ++trial) {
    const Vector12d q = folded_hinge(fold(rng), 0.2, rng);
    const HingeRest rest = rest_of(folded_hinge(0.3, 0.2, rng));
    const auto energy = [&](const Vector12d& y, Vector12d* gradient) {
      return energy_of(y, rest, stiffness, gradient);
    };
    Vector12d gradient;
    ASSERT_GT(energy(q, &gradient), 0.0);
    expect_no_net_force_or_torque(q, gradient);
    expect_rigid_motion_invariance(q, random_rotation(rng), Vec3::Random(), energy);
  }
}

TEST(HingeBending, DegenerateTrianglesGiveZeroForcesNotNaN) {
  const Vec3 x0(0, 0, 0), x1(1, 0, 0), x2(0.5, 1, 0), x3(0.5, -1, 0.3);
  const HingeRest rest = hinge_rest(x0, x1, x2, x3);
  Vector12d gradient;
  Matrix12d hessian;
  // x2 on the edge line, within 1e-12 of it, and a zero-length edge.
  for (const Vec3& degenerate_x2 : {Vec3(0.5, 0, 0), Vec3(0.3, 1e-12, 0), Vec3(2.0, 0, 0)}) {
    const double energy = hinge_bending_energy(x0, x1, degenerate_x2, x3, rest, 1.0, &gradient, &hessian);
    EXPECT_TRUE(std::isfinite(energy));
    EXPECT_EQ(gradient, Vector12d::Zero());
    EXPECT_EQ(hessian, Matrix12d::Zero());
  }
  const double energy = hinge_bending_energy(x0, x0, x2, x3, rest, 1.0, &gradient, &hessian);
  EXPECT_TRUE(std::isfinite(energy));
  EXPECT_EQ(gradient, Vector12d::Zero());
  EXPECT_EQ(hessian, Matrix12d::Zero());
  // Thin but above the threshold: large, finite forces.
  hinge_bending_energy(x0, x1, Vec3(0.5, 1e-6, 1e-6), x3, rest, 1.0, &gradient, &hessian);
  EXPECT_TRUE(gradient.allFinite());
  EXPECT_TRUE(hessian.allFinite());
  EXPECT_GT(gradient.norm(), 0.0);
  // Fully folded (theta = pi): finite.
  hinge_bending_energy(x0, x1, x2, Vec3(0.5, 1, 0), rest, 1.0, &gradient, &hessian);
  EXPECT_TRUE(gradient.allFinite());
  EXPECT_TRUE(hessian.allFinite());
  EXPECT_THROW(hinge_rest(x0, x1, Vec3(0.5, 0, 0), x3), std::invalid_argument);
  EXPECT_THROW(hinge_rest(x0, x0, x2, x3), std::invalid_argument);
}

}  // namespace
}  // namespace weft
