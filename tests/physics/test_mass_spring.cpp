// Mass-spring forces: the elastic force is minus the energy gradient (Taylor test), damping
// only opposes relative motion along the spring, and the lattice has Provot's spring counts.
#include "physics/mass_spring.hpp"

#include <gtest/gtest.h>

#include <random>

namespace weft {
namespace {

SpringSet random_springs(int n_vertices, int n_springs, std::mt19937& rng) {
  std::uniform_int_distribution<int> vertex(0, n_vertices - 1);
  std::uniform_real_distribution<double> unit(0.5, 1.5);
  SpringSet springs;
  springs.vertices.resize(2, n_springs);
  springs.rest_length.resize(n_springs);
  springs.stiffness.resize(n_springs);
  springs.damping.resize(n_springs);
  for (int s = 0; s < n_springs; ++s) {
    int i = vertex(rng), j = vertex(rng);
    while (j == i) j = vertex(rng);
    springs.vertices.col(s) << i, j;
    springs.rest_length[s] = unit(rng);
    springs.stiffness[s] = 100.0 * unit(rng);
    springs.damping[s] = unit(rng);
  }
  springs.kind_begin[1] = springs.kind_begin[2] = springs.kind_begin[3] = n_springs;
  return springs;
}

TEST(MassSpring, ElasticForceIsMinusEnergyGradientTaylorTest) {
  std::mt19937 rng(7);
  const int n = 12;
  const SpringSet springs = random_springs(n, 30, rng);
  // Drawn from the seeded generator: Eigen's Random() reads std::rand, whose state depends on
  // which tests ran before, and some draws put a spring near zero length, where the Taylor
  // ratios leave the asymptotic range.
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  const auto random_positions = [&] { return Positions(Positions::NullaryExpr(3, n, [&] { return coordinate(rng); })); };
  Positions x = random_positions();
  const Positions direction = random_positions();
  const Positions zero_velocity = Positions::Zero(3, n);
  Positions force = Positions::Zero(3, n);
  add_spring_forces(springs, x, zero_velocity, force);
  const double energy = spring_energy(springs, x);
  const double slope = -(force.array() * direction.array()).sum();  // dE/da along direction

  // First-order remainder |E(x + a d) - E(x) - a dE| must fall 4x each time a halves.
  double previous = 0.0;
  for (int k = 0; k < 6; ++k) {
    const double a = 1e-2 / (1 << k);
    const double remainder = std::abs(spring_energy(springs, x + a * direction) - energy - a * slope);
    if (k > 0) {
      EXPECT_NEAR(previous / remainder, 4.0, 0.12) << "halving " << k;
    }
    previous = remainder;
  }
}

TEST(MassSpring, DampingOpposesRelativeVelocityAlongTheSpringOnly) {
  SpringSet springs;
  springs.vertices.resize(2, 1);
  springs.vertices.col(0) << 0, 1;
  springs.rest_length.setConstant(1, 1.0);
  springs.stiffness.setConstant(1, 0.0);
  springs.damping.setConstant(1, 2.0);
  Positions x(3, 2);
  x.col(0) << 0, 0, 0;
  x.col(1) << 1, 0, 0;
  Positions v = Positions::Zero(3, 2);
  v.col(1) << 3.0, 5.0, 0.0;  // separating at 3 m/s along the spring, sliding at 5 m/s across it
  Positions force = Positions::Zero(3, 2);
  add_spring_forces(springs, x, v, force);
  EXPECT_NEAR(force(0, 1), -6.0, 1e-12);  // -gamma * 3
  EXPECT_NEAR(force(1, 1), 0.0, 1e-12);   // no damping across the spring
  EXPECT_NEAR((force.col(0) + force.col(1)).norm(), 0.0, 1e-12);  // f_ij = -f_ji
}

TEST(MassSpring, LatticeHasProvotsSpringCounts) {
  const int nx = 7, ny = 5;
  SpringStiffness params;
  params.stiffness[0] = params.stiffness[1] = params.stiffness[2] = 1.0;
  for (GridTriangulation triangulation : {GridTriangulation::regular, GridTriangulation::cross}) {
    const TriangleMesh grid = make_grid(nx, ny, 1.2, 0.8, triangulation);
    const SpringSet springs = make_lattice_springs(nx, ny, triangulation, grid.positions, params);
    EXPECT_EQ(springs.count(SpringKind::structural), (nx - 1) * ny + nx * (ny - 1));
    EXPECT_EQ(springs.count(SpringKind::shear), 2 * (nx - 1) * (ny - 1) * (triangulation == GridTriangulation::cross ? 2 : 1));
    EXPECT_EQ(springs.count(SpringKind::bend), (nx - 2) * ny + nx * (ny - 2));
    // Structural rest lengths are the lattice spacings.
    for (int s = springs.kind_begin[0]; s < springs.kind_begin[1]; ++s) {
      const double length = springs.rest_length[s];
      EXPECT_NEAR(length, 0.2, 1e-12);  // 1.2 / 6 along x, 0.8 / 4 along y
    }
  }
}

TEST(MassSpring, KindsWithoutStiffnessOrDampingAreNotPacked) {
  const TriangleMesh grid = make_grid(5, 5, 1.0, 1.0, GridTriangulation::regular);
  SpringStiffness params;
  params.stiffness[0] = 1.0;
  params.damping[2] = 0.5;
  const SpringSet springs = make_lattice_springs(5, 5, GridTriangulation::regular, grid.positions, params);
  EXPECT_EQ(springs.count(SpringKind::structural), 2 * 4 * 5);
  EXPECT_EQ(springs.count(SpringKind::shear), 0);  // an off term costs nothing
  EXPECT_EQ(springs.count(SpringKind::bend), 2 * 3 * 5);  // damping alone keeps the kind
}

TEST(MassSpring, SetSpringParamsChangesOneKindOnly) {
  const TriangleMesh grid = make_grid(4, 4, 1.0, 1.0, GridTriangulation::regular);
  SpringStiffness params;
  for (int k = 0; k < spring_kind_count; ++k) params.stiffness[k] = 10.0 * (k + 1);
  SpringSet springs = make_lattice_springs(4, 4, GridTriangulation::regular, grid.positions, params);
  set_spring_params(springs, SpringKind::shear, 99.0, 0.5);
  for (int s = 0; s < springs.size(); ++s) {
    const bool shear = s >= springs.kind_begin[1] && s < springs.kind_begin[2];
    EXPECT_EQ(springs.stiffness[s], shear ? 99.0 : (s < springs.kind_begin[1] ? 10.0 : 30.0));
  }
}

}  // namespace
}  // namespace weft
