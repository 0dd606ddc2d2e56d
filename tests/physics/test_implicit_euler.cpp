// Newton's method inside implicit Euler: with an exact (Cholesky) solve the gradient norm of the
// incremental potential falls quadratically near the solution, r_{k+1} <= C r_k^2, both where the
// Hessian needs no PSD projection (every spring stretched) and where compressed springs make the
// projected Hessian inexact (the Cholesky path solves the exact one wherever it is definite).
#include "physics/implicit_euler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/bending.hpp"
#include "sim/world.hpp"
#include "support/spring_cloth.hpp"

namespace weft {
namespace {

// A 7x7 cloth scaled by `stretch_x` and `stretch_z` in its plane with its whole border pinned,
// its middle thrown downwards.
Cloth stretched_drum(double stretch_x = 1.1, double stretch_z = 1.1) {
  const int n = 7;
  Cloth cloth = test::spring_grid_cloth(n, 0.6, 0.01, test::spring_params(100.0, 40.0, 10.0, 0.02));
  cloth.state.x.row(0) *= stretch_x;
  cloth.state.x.row(2) *= stretch_z;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int vertex = j * n + i;
      if (i == 0 || j == 0 || i == n - 1 || j == n - 1) {
        cloth.model.inverse_mass[vertex] = 0.0;
      } else {
        cloth.state.v(1, vertex) = -3.0 * std::sin(pi * i / (n - 1)) * std::sin(pi * j / (n - 1));
      }
    }
  }
  return cloth;
}

// Near the solution (r_k < r_0 / 5) and above the round-off floor, C_k = r_{k+1} / r_k^2 stays
// bounded; linear convergence at rate rho would make C_k = rho / r_k grow without bound.
void expect_quadratic_convergence(const std::vector<double>& r) {
  const double floor = 1e-12 * r.front();
  std::vector<double> constants;
  double last_contraction = 1.0;
  for (size_t k = 0; k + 1 < r.size(); ++k) {
    if (r[k] < 0.2 * r.front() && r[k + 1] > floor) {
      constants.push_back(r[k + 1] / (r[k] * r[k]));
      last_contraction = r[k + 1] / r[k];
    }
  }
  ASSERT_GE(constants.size(), 3u);
  for (double c : constants) {
    std::printf("C = %.3e\n", c);
    EXPECT_LT(c, 10.0 * constants.front());
  }
  // The last step above round-off contracts far more than any linear rate would.
  EXPECT_LT(last_contraction, 1e-3);
}

// One implicit Euler step of h = 1/24 s with Cholesky, Newton iterated down to round-off; prints
// the gradient norms r_k.
NewtonReport cholesky_step_to_round_off(Cloth& cloth) {
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings;
  settings.linear_solver = LinearSolverKind::cholesky;
  settings.newton_tolerance = 1e-14;
  settings.max_newton_iterations = 40;
  const NewtonReport report = solver.step(cloth, Vec3(0.0, -9.81, 0.0), 1.0 / 24.0, settings);
  const std::vector<double>& r = report.gradient_norms;
  for (size_t k = 0; k < r.size(); ++k) std::printf("r_%zu = %.3e\n", k, r[k]);
  return report;
}

double spring_length(const Cloth& cloth, int s) {
  const SpringSet& springs = cloth.model.springs;
  return (cloth.state.x.col(springs.vertices(1, s)) - cloth.state.x.col(springs.vertices(0, s))).norm();
}

TEST(ImplicitEuler, NewtonConvergesQuadraticallyNearTheSolution) {
  Cloth cloth = stretched_drum();
  const NewtonReport report = cholesky_step_to_round_off(cloth);
  const std::vector<double>& r = report.gradient_norms;

  // The premise: at the solution every spring is stretched, so the projected Hessian is exact.
  const SpringSet& springs = cloth.model.springs;
  for (int s = 0; s < springs.size(); ++s) {
    ASSERT_GT(spring_length(cloth, s), springs.rest_length[s]) << "spring " << s;
  }
  ASSERT_TRUE(cloth.state.x.allFinite());
  // The step was a real nonlinear solve, and it reached round-off.
  ASSERT_GE(r.size(), 4u);
  EXPECT_LT(r.back(), 1e-9 * r.front());

  expect_quadratic_convergence(r);
}

TEST(ImplicitEuler, CholeskyNewtonConvergesQuadraticallyWithCompressedSprings) {
  Cloth cloth = stretched_drum(1.1, 0.97);
  const NewtonReport report = cholesky_step_to_round_off(cloth);
  const std::vector<double>& r = report.gradient_norms;

  // The premise: springs are compressed at the solution, so element-wise projection would change
  // the Hessian there; yet the exact Hessian of the incremental potential is definite throughout.
  const SpringSet& springs = cloth.model.springs;
  int compressed = 0;
  for (int s = 0; s < springs.size(); ++s)
    compressed += spring_length(cloth, s) < 0.99 * springs.rest_length[s];
  ASSERT_GT(compressed, 0);
  EXPECT_EQ(report.projected_hessians, 0);
  ASSERT_GE(r.size(), 4u);
  EXPECT_LT(r.back(), 1e-9 * r.front());
  expect_quadratic_convergence(r);
}

TEST(ImplicitEuler, DefaultSettingsConvergeInFewIterations) {
  Cloth cloth = stretched_drum();
  ImplicitEulerSolver solver;
  for (LinearSolverKind kind : {LinearSolverKind::cholesky, LinearSolverKind::conjugate_gradient}) {
    Cloth copy = cloth;
    ImplicitEulerSettings settings;
    settings.linear_solver = kind;
    const NewtonReport& report = solver.step(copy, Vec3(0.0, -9.81, 0.0), 1.0 / 24.0, settings);
    EXPECT_TRUE(report.converged);
    EXPECT_LE(report.newton_iterations, 10);
  }
}

TEST(ImplicitEuler, StretchedStepsCutTheIterationsOfABucklingStep) {
  // A drum compressed to 90% of its rest size with its middle pushed down buckles within the step.
  // The projected Hessian drops the compressed springs' negative curvature, so full Newton steps
  // creep along the buckling mode; stretching a step to the minimum of the line's quadratic
  // (max_step_expansion) reaches the same tolerance in fewer iterations.
  int iterations[2] = {0, 0};
  int stretched[2] = {0, 0};
  for (const int expand : {0, 1}) {
    for (int trial = 0; trial < 4; ++trial) {
      Cloth cloth = stretched_drum(0.9 - 0.02 * trial, 0.9);
      ImplicitEulerSolver solver;
      ImplicitEulerSettings settings;
      settings.max_step_expansion = expand ? 4.0 : 1.0;
      settings.max_newton_iterations = 200;
      const NewtonReport& report = solver.step(cloth, Vec3(0.0, -9.81, 0.0), 1.0 / 24.0, settings);
      EXPECT_TRUE(report.converged) << expand << " " << trial;
      iterations[expand] += report.newton_iterations;
      stretched[expand] += report.stretched_steps;
    }
  }
  std::printf("Newton iterations without / with stretching: %d / %d (%d stretched)\n", iterations[0], iterations[1],
              stretched[1]);
  EXPECT_EQ(stretched[0], 0);
  EXPECT_GT(stretched[1], 0);
  EXPECT_LT(iterations[1], iterations[0]);
}

TEST(ImplicitEuler, ConjugateGradientSolvesFreeFallFromTheGravityGuess) {
  // A free cloth at rest falls by h^2 g in one step (its springs stay at rest length). Hung in a
  // vertical plane, so that gravity pulls along its springs, block Jacobi alone builds that smooth
  // translation slowly (tens of CG iterations on a stiff 24x24 cloth); the first solve starts
  // from the best multiple of the drop, which is the answer itself.
  Cloth cloth = test::spring_grid_cloth(24, 1.0, 0.01, test::spring_params(1e4, 1e3, 1.0, 0.0));
  cloth.state.x.row(1).swap(cloth.state.x.row(2));
  const Positions start = cloth.state.x;
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 60.0;
  ImplicitEulerSolver solver;
  const NewtonReport& report = solver.step(cloth, gravity, h, ImplicitEulerSettings{});
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.newton_iterations, 1);
  EXPECT_LE(report.linear_iterations, 1);
  for (int v = 0; v < cloth.num_vertices(); ++v) {
    EXPECT_LT((cloth.state.x.col(v) - start.col(v) - h * h * gravity).norm(), 1e-12) << v;
  }
}

TEST(ImplicitEuler, AFallingClothKeepsAcceleratingWithAToleranceJustBelowGravitysPull) {
  // The drape's tolerance (1e-2 m/s) and mass damping (0.1 /s) at h = 1/960 s: gravity's pull over
  // a step is |g| h = 0.0102 m/s, and once the damping takes 0.1 v h off it the inertial predictor
  // meets the tolerance (from v = 2.1 m/s). A step that accepted it would drop gravity's
  // acceleration: the cloth would glide at constant speed with every step "converged". Implicit
  // Euler's uniform fall is v' = (v + h g) / (1 + c h), which one Newton iteration a step reaches.
  Cloth cloth = test::spring_grid_cloth(6, 0.5, 0.01, test::spring_params(1e3, 1e2, 1.0, 0.0));
  cloth.model.mass_damping = 0.1;
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 960.0;
  ImplicitEulerSettings settings;
  settings.newton_tolerance = 1e-2;
  ASSERT_LT(settings.newton_tolerance, resting_start_residual(gravity, h));
  ImplicitEulerSolver solver;
  double expected = 0.0;  // the downward speed of implicit Euler's uniform fall
  int iterations = 0;
  for (int step = 0; step < 400; ++step) {
    const NewtonReport& report = solver.step(cloth, gravity, h, settings);
    ASSERT_TRUE(report.converged) << step;
    iterations += report.newton_iterations;
    expected = (expected + h * 9.81) / (1.0 + 0.1 * h);
  }
  EXPECT_GT(expected, 3.5);  // well past the 2.1 m/s where the predictor met the tolerance
  for (int v = 0; v < cloth.num_vertices(); ++v) {
    EXPECT_NEAR(-cloth.state.v(1, v), expected, 1e-9 * expected) << v;
    EXPECT_NEAR(cloth.state.v(0, v), 0.0, 1e-9) << v;
  }
  EXPECT_EQ(iterations, 400);  // one a step, from the start that already met the tolerance too
}

// A small membrane cloth with hinge bending, horizontal, pinned at two corners, as a World.
World small_hanging_cloth(double size, int resolution, double h, const std::string& linear_solver) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "gravity": [0, -9.81, 0],
    "solver": {"integrator": "implicit_euler", "newton": {"tolerance": 1e-5, "max_iterations": 60}},
    "cloths": [{
      "grid": {"triangulation": "alternating"},
      "transform": {"rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "membrane": {"young_modulus": 1e6, "poisson_ratio": 0.3, "thickness": 5e-4},
      "bending": {"stiffness": 1e-4},
      "thickness": 1e-4,
      "pins": {"corners": ["top_left", "top_right"]}}],
    "collision": {"enabled": false}})");
  scene["solver"]["time_step"] = h;
  scene["fps"] = 1.0 / h;
  scene["solver"]["newton"]["linear_solver"] = linear_solver;
  scene["cloths"][0]["grid"]["size"] = {size, size};
  scene["cloths"][0]["grid"]["resolution"] = {resolution, resolution};
  return build_world(parse_scene(scene, "<inline>"));
}

struct HangingRun {
  Positions x;
  int unconverged = 0;
  double largest_unreported_residual = 0.0;  // residual of a step reported converged
};

HangingRun run_hanging(double size, int resolution, double h, double duration, const std::string& linear_solver) {
  World world = small_hanging_cloth(size, resolution, h, linear_solver);
  HangingRun run;
  const int steps = static_cast<int>(std::lround(duration / h));
  for (int k = 0; k < steps; ++k) {
    world.step();
    const StepStats& stats = world.last_step_stats();
    run.unconverged += stats.unconverged_steps;
    if (stats.unconverged_steps == 0) {
      run.largest_unreported_residual = std::max(run.largest_unreported_residual, stats.residual);
    }
  }
  run.x = world.cloths()[0].state.x;
  return run;
}

// The default conjugate-gradient path against the Cholesky reference on cloths small or fine
// enough that a Hessian stiffening rigid motion would freeze them in the air while reporting
// convergence (a 1 cm 16x16 cloth falling 0.2 mm in 5 s instead of swinging down): the two end
// within 0.5% of the cloth's size of each other, and no step reported converged has a residual
// above the tolerance.
TEST(ImplicitEuler, SmallAndFineClothsMatchTheCholeskyReference) {
  struct Case {
    double size;
    int resolution;
    double h;
    double duration;
  };
  for (const Case c : {Case{0.01, 16, 1.0 / 30.0, 0.2}, Case{0.01, 16, 1.0 / 240.0, 0.1},
                       Case{0.1, 32, 1.0 / 30.0, 0.2}}) {
    const HangingRun cg = run_hanging(c.size, c.resolution, c.h, c.duration, "conjugate_gradient");
    const HangingRun reference = run_hanging(c.size, c.resolution, c.h, c.duration, "cholesky");
    const double fall = reference.x.row(1).maxCoeff() - reference.x.row(1).minCoeff();
    const double apart = (cg.x - reference.x).colwise().norm().maxCoeff();
    std::printf("size %g, %dx%d, h %.4g: sag %.3g m, CG vs Cholesky %.3g m, unconverged %d / %d\n", c.size,
                c.resolution, c.resolution, c.h, fall, apart, cg.unconverged, reference.unconverged);
    EXPECT_GT(fall, 0.2 * c.size) << "the cloth swings down";
    EXPECT_LT(apart, 5e-3 * c.size);
    EXPECT_LE(cg.largest_unreported_residual, 1e-5);
    EXPECT_LE(reference.largest_unreported_residual, 1e-5);
  }
}

// Leaving the hinges' Hessian out of CG's matrix (bending_hessian_share) changes the Newton
// iterates, not the answer or the residual each step reports: a 1 m 16x16 hanging cloth, swinging
// after 24 steps of h = 1/240 s, stepped four more times with the hinges kept, left out, and
// switched from step to step on one solver (its pattern rebuilt each time) agrees to 1e-8 m.
TEST(ImplicitEuler, TheHingesLeftOutOfTheMatrixChangeNeitherTheAnswerNorTheResidual) {
  const double h = 1.0 / 240.0;
  World world = small_hanging_cloth(1.0, 16, h, "conjugate_gradient");
  for (int k = 0; k < 24; ++k) world.step();
  const Cloth start = world.cloths()[0];
  const double share =
      bending_stiffness_rate(start.model.bending, start.model.rest_positions, start.model.inverse_mass) * h *
      h;
  ASSERT_GT(share, 0.0);
  ASSERT_LT(share, ImplicitEulerSettings{}.bending_hessian_share) << "the default leaves them out here";

  ImplicitEulerSettings kept;
  kept.newton_tolerance = 1e-7;
  kept.max_newton_iterations = 60;
  kept.bending_hessian_share = 0.0;
  ImplicitEulerSettings left_out = kept;
  left_out.bending_hessian_share = 1e9;
  left_out.hinges_out_of_matrix_iterations = 1000;
  const Vec3 gravity(0.0, -9.81, 0.0);
  Cloth with = start, without = start, switched = start;
  ImplicitEulerSolver with_solver, without_solver, switched_solver;
  for (int k = 0; k < 4; ++k) {
    const NewtonReport a = with_solver.step(with, gravity, h, kept);
    const NewtonReport b = without_solver.step(without, gravity, h, left_out);
    const NewtonReport c = switched_solver.step(switched, gravity, h, k % 2 == 0 ? left_out : kept);
    EXPECT_TRUE(a.converged && b.converged && c.converged) << "step " << k;
    EXPECT_LT(b.residual, kept.newton_tolerance);
    if (k == 0) {
      EXPECT_NE(a.gradient_norms, b.gradient_norms) << "another matrix, other iterates";
      EXPECT_EQ(a.full_matrix_steps, 0);
      EXPECT_EQ(b.full_matrix_steps, 0) << "hinges_out_of_matrix_iterations is past this step's iterations";
    }
    EXPECT_LT((with.state.x - without.state.x).colwise().norm().maxCoeff(), 1e-8) << "step " << k;
    EXPECT_LT((with.state.x - switched.state.x).colwise().norm().maxCoeff(), 1e-8) << "step " << k;
  }
}

// A step begun without the hinges in the matrix goes on with them after hinges_out_of_matrix_iterations:
// at 0 its iterates are the same as with the hinges always in (the switch comes before the first
// solve), after 2 it switches once and still ends at the same answer.
TEST(ImplicitEuler, AStepThatRunsLongWithoutTheHingesGoesOnWithThem) {
  const double h = 1.0 / 240.0;
  World world = small_hanging_cloth(1.0, 16, h, "conjugate_gradient");
  for (int k = 0; k < 24; ++k) world.step();
  const Cloth start = world.cloths()[0];
  ImplicitEulerSettings kept;
  kept.newton_tolerance = 1e-7;
  kept.max_newton_iterations = 60;
  kept.bending_hessian_share = 0.0;
  const Vec3 gravity(0.0, -9.81, 0.0);
  Cloth with = start;
  ImplicitEulerSolver with_solver;
  const NewtonReport reference = with_solver.step(with, gravity, h, kept);
  ASSERT_TRUE(reference.converged);
  ASSERT_GT(reference.newton_iterations, 2);

  for (const int out_of_matrix_iterations : {0, 2}) {
    SCOPED_TRACE(out_of_matrix_iterations);
    ImplicitEulerSettings switching = kept;
    switching.bending_hessian_share = 1e9;
    switching.hinges_out_of_matrix_iterations = out_of_matrix_iterations;
    Cloth cloth = start;
    ImplicitEulerSolver solver;
    const NewtonReport report = solver.step(cloth, gravity, h, switching);
    EXPECT_TRUE(report.converged);
    EXPECT_EQ(report.full_matrix_steps, 1);
    if (out_of_matrix_iterations == 0) {
      EXPECT_EQ(report.gradient_norms, reference.gradient_norms);
    } else {
      EXPECT_NE(report.gradient_norms, reference.gradient_norms);
    }
    EXPECT_LT((cloth.state.x - with.state.x).colwise().norm().maxCoeff(), 1e-8);
    // The next step begins without them again.
    const NewtonReport next = solver.step(cloth, gravity, h, switching);
    EXPECT_TRUE(next.converged);
    EXPECT_EQ(next.full_matrix_steps, 1);
  }
}

}  // namespace
}  // namespace weft
