// Global convergence order of the integrators on a smooth scene without contact or damping: a
// 6x6 spring cloth, pinned at two corners, falls and swings from rest under gravity. Positions
// at time T integrated with h, h/2, h/4, h/8 are compared with an explicit midpoint reference at
// h/256; the least-squares slope of log(error) against log(h) is the observed order. Volino et
// al. 1995's midpoint Euler-Cromer is also measured on a membrane cloth (StVK, hinge bending).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/explicit_midpoint.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/midpoint_euler_cromer.hpp"
#include "sim/world.hpp"
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

enum class Method { symplectic, midpoint, midpoint_euler_cromer, implicit };

Positions integrate(Method method, int steps, Cloth cloth = swinging_cloth()) {
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
        explicit_midpoint_step(cloth, gravity, h, workspace);
        break;
      case Method::midpoint_euler_cromer:
        midpoint_euler_cromer_step(cloth, gravity, h, workspace);
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
double observed_order(Method method, std::vector<double>& errors, const Cloth& cloth = swinging_cloth(),
                      const Positions* reference_positions = nullptr, int coarse = coarse_steps) {
  const Positions& reference = reference_positions ? *reference_positions : reference_solution();
  std::vector<double> log_h, log_e;
  for (int refinement : {1, 2, 4, 8}) {
    const double error = (integrate(method, refinement * coarse, cloth) - reference).lpNorm<Eigen::Infinity>();
    errors.push_back(error);
    log_h.push_back(std::log(duration / (refinement * coarse)));
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

TEST(IntegratorConvergence, MidpointEulerCromerIsSecondOrder) {
  std::vector<double> errors;
  const double slope = observed_order(Method::midpoint_euler_cromer, errors);
  print_errors("midpoint Euler-Cromer", errors, slope);
  EXPECT_NEAR(slope, 2.0, 0.15);
}

// A 6x6 membrane cloth (StVK, hinge bending) 0.5 m wide pinned at two corners, swinging from
// rest, with a given compression factor (the modulus under compression over the one under
// tension: below 1 the stress-strain law has a kink at zero strain).
Cloth membrane_cloth(double compression_factor) {
  nlohmann::json scene = nlohmann::json::parse(R"({"cloths": [{
      "grid": {"size": [0.5, 0.5], "resolution": [6, 6], "triangulation": "alternating"},
      "density": 0.2,
      "springs": {"structural": {"stiffness": 0, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                  "bend": {"stiffness": 0, "damping": 0}},
      "membrane": {"young_modulus": 2e4, "poisson_ratio": 0.3, "thickness": 5e-4},
      "bending": {"stiffness": 1e-5},
      "pins": {"corners": ["top_left", "top_right"]}}]})");
  scene["cloths"][0]["membrane"]["compression_factor"] = compression_factor;
  World world = build_world(parse_scene(scene, "<inline>"));
  return world.cloths()[0];
}

TEST(IntegratorConvergence, MidpointEulerCromerIsSecondOrderOnAMembrane) {
  // h0 = T / 125 (membrane forces cost more than springs'); the explicit midpoint reference at
  // h0 / 64. With the kink (compression factor 0.1, the scenes' default) the force is only
  // Lipschitz where triangles cross zero strain, which can cost the order; on this swinging,
  // mostly stretched cloth the observed order is 2 as well. Printed, asserted for 1 only.
  constexpr int coarse = 125;
  for (const double compression_factor : {1.0, 0.1}) {
    const Cloth cloth = membrane_cloth(compression_factor);
    const Positions reference = integrate(Method::midpoint, 64 * coarse, cloth);
    std::vector<double> errors;
    const double slope = observed_order(Method::midpoint_euler_cromer, errors, cloth, &reference, coarse);
    std::printf("compression factor %.1f: ", compression_factor);
    print_errors("midpoint Euler-Cromer on a membrane", errors, slope);
    EXPECT_GT((reference - cloth.state.x).lpNorm<Eigen::Infinity>(), 0.05) << "the cloth swings";
    if (compression_factor == 1.0) {
      EXPECT_NEAR(slope, 2.0, 0.15);
    }
  }
}

TEST(IntegratorConvergence, ImplicitEulerIsFirstOrder) {
  std::vector<double> errors;
  const double slope = observed_order(Method::implicit, errors);
  print_errors("implicit", errors, slope);
  EXPECT_NEAR(slope, 1.0, 0.15);
}

}  // namespace
}  // namespace weft
