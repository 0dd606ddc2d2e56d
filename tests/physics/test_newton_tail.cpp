// The restricted tail of a Newton solve (physics/newton_tail.hpp): it moves only the free
// vertices near those whose residual is above the tolerance, lowers the incremental potential,
// keeps the whole cloth's gradient exact (checked against a fresh evaluation over every element),
// and inside ImplicitEulerSolver the residual a step reports is the whole cloth's.
#include "physics/newton_tail.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/implicit_euler.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A 16x16, 0.3 m membrane cloth with hinges of the given bending model and mass damping, pinned
// at two corners, after `steps` steps of h = 1/240 s swinging down.
Cloth swinging_cloth(int steps, const std::string& bending_model = "dihedral") {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "gravity": [0, -9.81, 0],
    "solver": {"integrator": "implicit_euler", "time_step": 0.004166666666666667,
               "newton": {"tolerance": 1e-4, "max_iterations": 60}},
    "fps": 240,
    "cloths": [{
      "grid": {"size": [0.3, 0.3], "resolution": [16, 16], "triangulation": "alternating"},
      "transform": {"rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "membrane": {"young_modulus": 5e6, "poisson_ratio": 0.3, "thickness": 5e-4, "compression_factor": 0.01},
      "bending": {"stiffness": 2e-5},
      "mass_damping": 0.1,
      "thickness": 1e-3,
      "pins": {"corners": ["top_left", "top_right"]}}],
    "collision": {"enabled": false}})");
  scene["cloths"][0]["bending"]["model"] = bending_model;
  World world = build_world(parse_scene(scene, "<inline>"));
  for (int k = 0; k < steps; ++k) world.step();
  return world.cloths()[0];
}

// The incremental potential and its pin-masked gradient over every element, as the solver
// evaluates it.
double full_potential(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                      const Positions& x_hat, const Positions& x, Positions& gradient) {
  gradient.setZero(3, x.cols());
  const HessianStencils none;
  double value = evaluate_mass_quadratic(model.mass, 1.0 / (h * h), x, x_hat, &gradient, nullptr);
  value += evaluate_potential(model, gravity, x, &gradient, nullptr, none, false);
  value += evaluate_dissipation(model, x_start, x, h, &gradient, nullptr, none);
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (model.inverse_mass[i] == 0.0) gradient.col(i).setZero();
  }
  return value;
}

class NewtonTailForBending : public testing::TestWithParam<std::string> {};

TEST_P(NewtonTailForBending, FinishesALocalResidualMovingOnlyItsRegionAndKeepsTheGradientExact) {
  Cloth cloth = swinging_cloth(12, GetParam());
  const ClothModel& model = cloth.model;
  ASSERT_TRUE(NewtonTail::supports(model));
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 240.0;
  const double tolerance = 1e-4;
  // The converged step from this state, then two vertices in the middle pushed off it by a
  // fraction of a micrometre: a residual ~100x the tolerance on a few vertices, as a global
  // Newton iteration leaves it near the end of a step.
  const Positions x_start = cloth.state.x;
  const Positions x_hat = x_start + h * cloth.state.v;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings tight;
  tight.newton_tolerance = 1e-9;
  tight.restricted_tail_share = 0.0;
  tight.max_newton_iterations = 60;
  ASSERT_TRUE(solver.step(cloth, gravity, h, tight).converged);
  Positions x = cloth.state.x;
  const int a = 8 * 16 + 7, b = 8 * 16 + 8;
  x.col(a) += Vec3(0.0, 6e-8, 3e-8);
  x.col(b) += Vec3(3e-8, -3e-8, 0.0);
  const Positions pushed = x;

  Positions gradient;
  const double before = full_potential(model, gravity, h, x_start, x_hat, x, gradient);
  const double residual_before = newton_residual(gradient, model.inverse_mass, h);
  ASSERT_GT(residual_before, 10.0 * tolerance);
  ASSERT_LT(residual_before, 1000.0 * tolerance);

  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  NewtonTail tail;
  tail.prepare(model);
  NewtonTailSettings settings;
  settings.tolerance = tolerance;
  settings.largest_share = 0.2;
  const int iterations =
      tail.iterate(model, gravity, h, x_start, x_hat, nullptr, settings, hessian, stencils, x, gradient);
  EXPECT_GE(iterations, 1);

  Positions fresh;
  const double after = full_potential(model, gravity, h, x_start, x_hat, x, fresh);
  EXPECT_LT(after, before);
  const double scale = fresh.colwise().norm().maxCoeff();
  EXPECT_LT((gradient - fresh).colwise().norm().maxCoeff(), 1e-9 * scale) << "the gradient it kept";
  const double residual_after = newton_residual(fresh, model.inverse_mass, h);
  std::printf("residual %.3e -> %.3e m/s in %d restricted iterations\n", residual_before, residual_after,
              iterations);
  EXPECT_LT(residual_after, tolerance);
  int moved = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (x.col(i) == pushed.col(i)) continue;
    ++moved;
    EXPECT_GT(model.inverse_mass[i], 0.0) << "a pinned vertex moved: " << i;
  }
  EXPECT_GT(moved, 0);
  EXPECT_LT(moved, x.cols() / 2) << "the whole cloth moved, not a region";
}

INSTANTIATE_TEST_SUITE_P(NewtonTail, NewtonTailForBending, testing::Values("dihedral", "quadratic"));

TEST(NewtonTail, TheResidualAStepReportsIsTheWholeCloths) {
  // Steps of the swinging cloth with the tail on: whenever it ran, the residual reported equals
  // one evaluated afresh over every element at the step's end, and a step reported converged is.
  Cloth cloth = swinging_cloth(0);
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 240.0;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings;
  settings.newton_tolerance = 1e-4;
  settings.max_newton_iterations = 60;
  settings.restricted_tail_share = 0.2;
  int restricted = 0;
  for (int k = 0; k < 60; ++k) {
    const Positions x_start = cloth.state.x;
    const Positions x_hat = x_start + h * cloth.state.v;
    const NewtonReport& report = solver.step(cloth, gravity, h, settings);
    restricted += report.restricted_iterations;
    Positions gradient;
    full_potential(cloth.model, gravity, h, x_start, x_hat, cloth.state.x, gradient);
    const double residual = newton_residual(gradient, cloth.model.inverse_mass, h);
    EXPECT_NEAR(report.residual, residual, 1e-9 * std::max(residual, 1.0)) << "step " << k;
    if (report.converged) {
      EXPECT_LT(residual, settings.newton_tolerance) << "step " << k;
    }
  }
  std::printf("%d restricted iterations over 60 steps\n", restricted);
  EXPECT_GT(restricted, 0);
}

}  // namespace
}  // namespace weft
