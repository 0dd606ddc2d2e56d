// Global convergence order of the three integrators on a smooth scene without contact or
// damping: a 6x6 spring cloth, pinned at two corners, falls and swings from rest under gravity.
// Positions at time T integrated with h, h/2, h/4, h/8 are compared with a midpoint reference
// at h/256; the least-squares slope of log(error) against log(h) is the observed order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "physics/implicit_euler.hpp"
#include "physics/midpoint_euler.hpp"
#include "physics/symplectic_euler.hpp"
#include "support/spring_cloth.hpp"

namespace weft {
namespace {

constexpr int grid_n = 6;

// A flat 6x6 cloth 0.5 m wide, 10 g per vertex, pinned at the two corners of one edge.
Cloth swinging_cloth() {
  Cloth cloth = test::spring_grid_cloth(grid_n, 0.5, 0.01, test::spring_params(10.0, 4.0, 1.0));
  cloth.model.inverse_mass[(grid_n - 1) * grid_n] = 0.0;
  cloth.model.inverse_mass[grid_n * grid_n - 1] = 0.0;
  return cloth;
}

const Vec3 gravity(0.0, -9.81, 0.0);
constexpr double duration = 0.25;        // s
constexpr int coarse_steps = 500;        // h0 = T / 500 = 5e-4 s

enum class Method { symplectic, midpoint, implicit };

Positions integrate(Method method, int steps) {
  Cloth cloth = swinging_cloth();
  const double h = duration / steps;
  ExplicitWorkspace workspace;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings;
  settings.linear_solver = LinearSolverKind::cholesky;
  settings.newton_tolerance = 1e-10;  // m/s: Newton error ~1e-10 T, far below the O(h) error
  settings.max_newton_iterations = 50;
  for (int k = 0; k < steps; ++k) {
    switch (method) {
      case Method::symplectic:
        symplectic_euler_step(cloth, gravity, h);
        break;
      case Method::midpoint:
        midpoint_step(cloth, gravity, h, workspace);
        break;
      case Method::implicit:
        solver.step(cloth, gravity, h, settings);
        break;
    }
  }
  return cloth.state.x;
}

const Positions& reference_solution() {
  static const Positions reference = integrate(Method::midpoint, 256 * coarse_steps);
  return reference;
}

// Least-squares slope of log(error) against log(h) over h0, h0/2, h0/4, h0/8.
double observed_order(Method method, std::vector<double>& errors) {
  const Positions& reference = reference_solution();
  std::vector<double> log_h, log_e;
  for (int refinement : {1, 2, 4, 8}) {
    const double error = (integrate(method, refinement * coarse_steps) - reference).lpNorm<Eigen::Infinity>();
    errors.push_back(error);
    log_h.push_back(std::log(duration / (refinement * coarse_steps)));
    log_e.push_back(std::log(error));
  }
  const Eigen::Map<const Eigen::VectorXd> lh(log_h.data(), 4), le(log_e.data(), 4);
  const Eigen::VectorXd centred_h = lh.array() - lh.mean();
  return centred_h.dot(le.array().matrix() - Eigen::VectorXd::Constant(4, le.mean())) / centred_h.squaredNorm();
}

void print_errors(const char* name, const std::vector<double>& errors, double slope) {
  std::printf("%s: errors %.3e %.3e %.3e %.3e, slope %.3f\n", name, errors[0], errors[1], errors[2], errors[3],
              slope);
}

TEST(IntegratorConvergence, SceneIsInTheAsymptoticRegime) {
  Cloth cloth = swinging_cloth();
  const double omega = test::largest_frequency(cloth.model, cloth.state.x);
  const double h0 = duration / coarse_steps;
  std::printf("largest frequency %.1f rad/s, omega h0 = %.3f\n", omega, omega * h0);
  // Even the stiffest mode is resolved by the coarsest step (~60 steps per period).
  EXPECT_LT(omega * h0, 0.11);
  // The motion is large: the free corners fall several centimetres, far above every error.
  const Positions& reference = reference_solution();
  EXPECT_GT((reference - cloth.state.x).lpNorm<Eigen::Infinity>(), 0.1);
}

TEST(IntegratorConvergence, SymplecticEulerIsFirstOrder) {
  std::vector<double> errors;
  const double slope = observed_order(Method::symplectic, errors);
  print_errors("symplectic", errors, slope);
  EXPECT_NEAR(slope, 1.0, 0.15);
}

TEST(IntegratorConvergence, MidpointIsSecondOrder) {
  std::vector<double> errors;
  const double slope = observed_order(Method::midpoint, errors);
  print_errors("midpoint", errors, slope);
  EXPECT_NEAR(slope, 2.0, 0.15);
}

TEST(IntegratorConvergence, ImplicitEulerIsFirstOrder) {
  std::vector<double> errors;
  const double slope = observed_order(Method::implicit, errors);
  print_errors("implicit", errors, slope);
  EXPECT_NEAR(slope, 1.0, 0.15);
}

}  // namespace
}  // namespace weft
