// Quadratic bending (flat rest shapes): the closed-form energy of an isometric fold, zero on every
// affine image of the rest hinge, derivatives by a Taylor test and an exact constant Hessian,
// rigid-motion invariance, a gradient that stays bounded as a wing collapses (where the dihedral
// angle's grows as 1/height), and the model refusing a curved rest mesh.
#include "physics/quadratic_bending.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/mesh_generators.hpp"
#include "core/topology.hpp"
#include "physics/bending.hpp"
#include "physics/hinge_bending.hpp"
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

double energy_of(const Vector12d& q, const QuadraticHinge& hinge, double stiffness, Vector12d* gradient = nullptr) {
  return quadratic_bending_energy(at(q, 0), at(q, 1), at(q, 2), at(q, 3), hinge, stiffness, gradient);
}

Vector12d moved_rigidly(const Vector12d& q, const Mat3& rotation, const Vec3& shift) {
  Vector12d moved;
  for (int i = 0; i < 4; ++i) moved.segment<3>(3 * i) = rotation * at(q, i) + shift;
  return moved;
}

// A flat, deliberately irregular hinge in the XY plane: edge (0,0,0)-(1.3,0,0), x2 above, x3 below
// (an obtuse angle at x1 in the lower triangle).
Vector12d flat_hinge() {
  Vector12d q;
  q << 0.0, 0.0, 0.0, 1.3, 0.0, 0.0, 0.45, 0.8, 0.0, 1.6, -0.5, 0.0;
  return q;
}

// The flat hinge with its x3 wing folded by theta about the edge (no stretching).
Vector12d folded(double theta) {
  Vector12d q = flat_hinge();
  q.segment<3>(9) = Eigen::AngleAxisd(theta, Vec3::UnitX()).toRotationMatrix() * at(q, 3);
  return q;
}

QuadraticHinge rest_of(const Vector12d& q) { return quadratic_hinge_rest(at(q, 0), at(q, 1), at(q, 2), at(q, 3)); }

Matrix12d hessian_of(const QuadraticHinge& hinge, double stiffness) {
  const Eigen::Matrix4d c = quadratic_bending_hessian_coefficients(hinge, stiffness);
  Matrix12d h = Matrix12d::Zero();
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) h.block<3, 3>(3 * i, 3 * j) = c(i, j) * Mat3::Identity();
  }
  return h;
}

TEST(QuadraticBending, AnIsometricFoldCostsFourSineSquaredOfHalfTheAngle) {
  const Vector12d rest = flat_hinge();
  const QuadraticHinge hinge = rest_of(rest);
  const double weight = hinge_rest(at(rest, 0), at(rest, 1), at(rest, 2), at(rest, 3)).weight;
  const double stiffness = 0.7;
  std::mt19937 rng(3);
  for (double theta : {-3.0, -1.2, -0.3, 0.01, 0.5, 1.9, 3.1}) {
    const Vector12d q = moved_rigidly(folded(theta), random_rotation(rng), Vec3::Random());
    const double expected = stiffness * weight * 4.0 * std::pow(std::sin(0.5 * theta), 2);
    EXPECT_NEAR(energy_of(q, hinge, stiffness), expected, 1e-12 * weight * stiffness) << "theta " << theta;
  }
  // To second order in theta the dihedral model's energy, stiffness * weight * theta^2.
  const HingeRest dihedral = hinge_rest(at(rest, 0), at(rest, 1), at(rest, 2), at(rest, 3));
  const Vector12d small = folded(1e-3);
  const double dihedral_energy =
      hinge_bending_energy(at(small, 0), at(small, 1), at(small, 2), at(small, 3), dihedral, stiffness, nullptr, nullptr);
  EXPECT_NEAR(energy_of(small, hinge, stiffness) / dihedral_energy, 1.0, 1e-6);
}

TEST(QuadraticBending, EveryAffineImageOfTheFlatRestIsStressFree) {
  const Vector12d rest = flat_hinge();
  const QuadraticHinge hinge = rest_of(rest);
  EXPECT_NEAR(hinge.weights.sum(), 0.0, 1e-14);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> entry(-2.0, 2.0);
  for (int trial = 0; trial < 5; ++trial) {
    Mat3 map;
    for (int k = 0; k < 9; ++k) map.data()[k] = entry(rng);  // stretches, shears, even flips
    const Vec3 shift = Vec3::Random();
    Vector12d q;
    for (int i = 0; i < 4; ++i) q.segment<3>(3 * i) = map * at(rest, i) + shift;
    Vector12d gradient;
    EXPECT_LT(energy_of(q, hinge, 1.0, &gradient), 1e-24) << trial;
    EXPECT_LT(gradient.norm(), 1e-11) << trial;
  }
}

TEST(QuadraticBending, GradientTaylorTestAndTheConstantHessianIsExact) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  const QuadraticHinge hinge = rest_of(flat_hinge());
  const double stiffness = 0.7;
  const Matrix12d hessian = hessian_of(hinge, stiffness);
  EXPECT_LE((hessian - hessian.transpose()).norm(), 1e-14 * hessian.norm());
  for (int trial = 0; trial < 6; ++trial) {
    Vector12d q = folded(normal(rng)), d;
    for (int i = 0; i < 12; ++i) {
      q[i] += 0.2 * normal(rng);  // stretched as well as folded
      d[i] = normal(rng);
    }
    Vector12d gradient;
    const double energy = energy_of(q, hinge, stiffness, &gradient);
    const auto remainder = [&](double a) {
      return std::abs(energy_of(q + a * d, hinge, stiffness) - energy - a * gradient.dot(d));
    };
    EXPECT_TRUE(all_near_quarter(halving_ratios(remainder, 1e-2, 5))) << trial;
    // The gradient is linear in the positions: moving by a d changes it by exactly a H d.
    for (double a : {1e-3, 0.1, 1.0}) {
      Vector12d moved;
      energy_of(q + a * d, hinge, stiffness, &moved);
      EXPECT_LE((moved - gradient - a * hessian * d).norm(), 1e-12 * (gradient.norm() + a * (hessian * d).norm()));
    }
    // Positive semi-definite: the energy is a sum of squares.
    EXPECT_GE(d.dot(hessian * d), 0.0);
  }
}

TEST(QuadraticBending, RigidMotionInvariantWithoutNetForceOrTorque) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> fold(-3.0, 3.0);
  const QuadraticHinge hinge = rest_of(flat_hinge());
  const auto energy = [&](const Vector12d& q, Vector12d* gradient) { return energy_of(q, hinge, 1.3, gradient); };
  for (int trial = 0; trial < 8; ++trial) {
    const Vector12d q = folded(fold(rng));
    Vector12d gradient;
    ASSERT_GT(energy(q, &gradient), 0.0);
    expect_no_net_force_or_torque(q, gradient);
    expect_rigid_motion_invariance(q, random_rotation(rng), Vec3::Random(), energy);
  }
}

// A folded hinge whose x2 wing collapses onto the edge: the dihedral angle's gradient grows as
// 1/height, the quadratic model's stays where it was.
TEST(QuadraticBending, TheGradientStaysBoundedAsAWingCollapses) {
  const Vector12d rest = flat_hinge();
  const QuadraticHinge quadratic = rest_of(rest);
  const HingeRest dihedral = hinge_rest(at(rest, 0), at(rest, 1), at(rest, 2), at(rest, 3));
  const auto gradients = [&](double height) {
    Vector12d q = folded(1.0);
    q.segment<3>(6) = Vec3(0.45, height, 0.0);
    Vector12d quadratic_gradient, dihedral_gradient;
    energy_of(q, quadratic, 1.0, &quadratic_gradient);
    hinge_bending_energy(at(q, 0), at(q, 1), at(q, 2), at(q, 3), dihedral, 1.0, &dihedral_gradient, nullptr);
    return std::make_pair(quadratic_gradient.norm(), dihedral_gradient.norm());
  };
  const auto [quadratic_tall, dihedral_tall] = gradients(0.8);
  const auto [quadratic_flat, dihedral_flat] = gradients(1e-6);
  EXPECT_LT(quadratic_flat, 1.5 * quadratic_tall);
  EXPECT_GT(dihedral_flat, 1e4 * dihedral_tall);
}

TEST(QuadraticBending, TheModelTakesOnlyAFlatRestMesh) {
  const TriangleMesh grid = make_grid(6, 5, 1.0, 0.8, GridTriangulation::alternating);
  const MeshTopology grid_topology = build_topology(grid.triangles, grid.num_vertices());
  const BendingTerm flat = make_bending_term(grid_topology, grid.positions, 1e-3, BendingModel::quadratic);
  EXPECT_EQ(flat.model, BendingModel::quadratic);
  EXPECT_GT(flat.hinges.cols(), 0);
  EXPECT_EQ(flat.quadratic.size(), static_cast<size_t>(flat.hinges.cols()));
  EXPECT_TRUE(flat.rest.empty());

  const TriangleMesh sphere = make_uv_sphere(0.2, 12, 6);
  const MeshTopology sphere_topology = build_topology(sphere.triangles, sphere.num_vertices());
  const BendingTerm dihedral = make_bending_term(sphere_topology, sphere.positions, 1e-3, BendingModel::dihedral);
  EXPECT_EQ(dihedral.rest.size(), static_cast<size_t>(dihedral.hinges.cols()));
  try {
    make_bending_term(sphere_topology, sphere.positions, 1e-3, BendingModel::quadratic);
    FAIL() << "a curved rest mesh was accepted by the quadratic model";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("flat rest mesh"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace weft
