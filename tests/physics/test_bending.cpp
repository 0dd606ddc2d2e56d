// The bending term's stiffness against inertia (bending_stiffness_rate), which decides whether
// implicit Euler's CG matrix keeps the hinges' Hessian: on one hinge it is the wing tip's
// Gauss-Newton diagonal 2 k w / height^2 over the tip's mass, it follows the stiffness, and the
// quadratic model (whose exact Hessian is always kept) reports it as infinite.
#include "physics/bending.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/mesh_generators.hpp"
#include "core/topology.hpp"

namespace weft {
namespace {

// Two triangles on the edge (0,0,0)-(1,0,0), tips at heights 0.5 and 0.25, flat.
struct OneHinge {
  Positions positions = Positions(3, 4);
  Triangles triangles = Triangles(3, 2);
  OneHinge() {
    positions << 0.0, 1.0, 0.3, 0.6,  //
        0.0, 0.0, 0.5, -0.25,         //
        0.0, 0.0, 0.0, 0.0;
    triangles << 0, 1,  //
        1, 0,           //
        2, 3;
  }
  BendingTerm term(double stiffness) const {
    return make_bending_term(build_topology(triangles, 4), positions, stiffness, BendingModel::dihedral);
  }
};

TEST(Bending, StiffnessRateIsTheWingTipsGaussNewtonDiagonalOverItsMass) {
  const OneHinge hinge;
  const double stiffness = 2e-3;
  const BendingTerm term = hinge.term(stiffness);
  ASSERT_EQ(term.hinges.cols(), 1);
  const double weight = 3.0 * 1.0 / (0.25 + 0.125);  // 3 |e|^2 / (A1 + A2)
  const double curvature = 2.0 * stiffness * weight;
  // Only one tip free at a time: its diagonal is curvature / height^2 (|grad theta| = 1 / height).
  Eigen::VectorXd inverse_mass = Eigen::VectorXd::Zero(4);
  inverse_mass[2] = 1.0 / 0.01;
  EXPECT_NEAR(bending_stiffness_rate(term, hinge.positions, inverse_mass), curvature / (0.5 * 0.5) / 0.01,
              1e-9);
  inverse_mass.setZero();
  inverse_mass[3] = 1.0 / 0.01;
  const double low_tip = curvature / (0.25 * 0.25) / 0.01;
  EXPECT_NEAR(bending_stiffness_rate(term, hinge.positions, inverse_mass), low_tip, 1e-9);
  // All free with equal masses: the largest vertex wins (the lower wing's tip or an edge end).
  inverse_mass.setConstant(1.0 / 0.01);
  EXPECT_GE(bending_stiffness_rate(term, hinge.positions, inverse_mass), low_tip * (1.0 - 1e-12));
  // Linear in the stiffness.
  EXPECT_NEAR(bending_stiffness_rate(hinge.term(2.0 * stiffness), hinge.positions, inverse_mass),
              2.0 * bending_stiffness_rate(term, hinge.positions, inverse_mass), 1e-9);
}

TEST(Bending, StiffnessRateGrowsAsTheFourthPowerOfTheResolution) {
  // A fixed sheet with twice the vertices a side: edges and heights halve (curvature / height^2
  // x4, the weight unchanged), vertex masses quarter (x4).
  const auto rate = [](int n) {
    const TriangleMesh grid = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
    const BendingTerm term = make_bending_term(build_topology(grid.triangles, grid.num_vertices()),
                                               grid.positions, 1e-4, BendingModel::dihedral);
    const double vertex_mass = 0.2 / ((n - 1) * (n - 1));  // interior vertices of a 0.2 kg/m^2 sheet
    return bending_stiffness_rate(term, grid.positions, Eigen::VectorXd::Constant(n * n, 1.0 / vertex_mass));
  };
  EXPECT_NEAR(rate(33) / rate(17), 16.0, 1e-9 * 16.0);
}

TEST(Bending, StiffnessRateOfTheQuadraticModelIsInfiniteAndOfNoHingesZero) {
  const OneHinge hinge;
  const BendingTerm quadratic =
      make_bending_term(build_topology(hinge.triangles, 4), hinge.positions, 1e-3, BendingModel::quadratic);
  const Eigen::VectorXd inverse_mass = Eigen::VectorXd::Ones(4);
  EXPECT_EQ(bending_stiffness_rate(quadratic, hinge.positions, inverse_mass),
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(bending_stiffness_rate(BendingTerm{}, hinge.positions, inverse_mass), 0.0);
}

}  // namespace
}  // namespace weft
