// Integrators at the extremes: the symplectic Euler stability limit h < 2/omega_max measured by
// bisection (one spring, a small cloth, a cloth whose vertex masses span 1e-3..1e3); implicit
// Euler on the same mass ratios and on nearly degenerate triangles; exact momentum balance in
// free fall for every integrator; energy of undamped symplectic Euler over 1e5 steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "physics/adaptive_stepping.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/explicit_midpoint.hpp"
#include "physics/midpoint_euler_cromer.hpp"
#include "physics/symplectic_euler.hpp"
#include "physics/xpbd.hpp"
#include "support/spring_cloth.hpp"

namespace weft {
namespace {

// Which explicit scheme the stability searches below step with.
enum class Scheme { symplectic_euler, midpoint_euler_cromer };

// Does the scheme with step h keep a small perturbation of the rest state small? Unstable
// means the displacement from rest grew 1000-fold within `steps` steps (a step just above the
// limit grows like exp(2 sqrt(delta) n); one just below stays within ~1/sqrt(2 delta)).
bool symplectic_stays_bounded(const Cloth& start, double h, int steps, Scheme scheme = Scheme::symplectic_euler) {
  Cloth cloth = start;
  ExplicitWorkspace workspace;
  const double initial = (cloth.state.x - cloth.model.rest_positions).lpNorm<Eigen::Infinity>();
  for (int k = 0; k < steps; ++k) {
    if (scheme == Scheme::symplectic_euler) {
      symplectic_euler_step(cloth, Vec3::Zero(), h);
    } else {
      midpoint_euler_cromer_step(cloth, Vec3::Zero(), h, workspace);
    }
    if (k % 64 == 0 && !((cloth.state.x - cloth.model.rest_positions).lpNorm<Eigen::Infinity>() < 1e3 * initial)) {
      return false;
    }
  }
  return (cloth.state.x - cloth.model.rest_positions).lpNorm<Eigen::Infinity>() < 1e3 * initial;
}

// Largest stable h by bisection in [lo, hi] (lo stable, hi unstable) to relative width 1e-5.
double largest_stable_step(const Cloth& start, double lo, double hi, int steps,
                           Scheme scheme = Scheme::symplectic_euler) {
  EXPECT_TRUE(symplectic_stays_bounded(start, lo, steps, scheme));
  EXPECT_FALSE(symplectic_stays_bounded(start, hi, steps, scheme));
  while (hi - lo > 1e-5 * lo) {
    const double mid = 0.5 * (lo + hi);
    (symplectic_stays_bounded(start, mid, steps, scheme) ? lo : hi) = mid;
  }
  return lo;
}

// Every vertex displaced randomly by up to `amplitude` (all three axes), at rest.
void perturb(Cloth& cloth, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    if (cloth.model.inverse_mass[i] == 0.0) continue;
    for (int r = 0; r < 3; ++r) cloth.state.x(r, i) += amplitude * unit(rng);
  }
}

// Vertex 0 pinned at the origin, vertex 1 of mass m on a spring of rest length 1 along x.
Cloth spring_oscillator(double mass, double stiffness) {
  ClothModel model;
  model.rest_positions.resize(3, 2);
  model.rest_positions.col(0) << 0, 0, 0;
  model.rest_positions.col(1) << 1, 0, 0;
  model.mass = Eigen::Vector2d(1.0, mass);
  model.inverse_mass = Eigen::Vector2d(0.0, 1.0 / mass);
  model.springs.vertices.resize(2, 1);
  model.springs.vertices.col(0) << 0, 1;
  model.springs.rest_length.setConstant(1, 1.0);
  model.springs.stiffness.setConstant(1, stiffness);
  model.springs.damping.setConstant(1, 0.0);
  model.springs.kind_begin[1] = model.springs.kind_begin[2] = model.springs.kind_begin[3] = 1;
  return make_cloth(std::move(model));
}

TEST(IntegratorStability, SymplecticEulerLimitOfOneSpringIsTwoSqrtMassOverStiffness) {
  // k/m from 1 to 1e8 s^-2, with both heavy and light masses.
  for (const auto& [mass, stiffness] : {std::pair{1.0, 1.0}, {0.01, 1.0}, {1e-3, 10.0}, {10.0, 1e5}, {1e-4, 1e4}}) {
    Cloth cloth = spring_oscillator(mass, stiffness);
    cloth.state.x(0, 1) += 1e-6;  // a stretch along the spring: the motion is exactly linear
    const double predicted = 2.0 * std::sqrt(mass / stiffness);
    const double measured = largest_stable_step(cloth, 0.9 * predicted, 1.1 * predicted, 20000);
    std::printf("k/m = %.0e: h_max = %.6e, 2 sqrt(m/k) = %.6e, ratio %.6f\n", stiffness / mass, measured, predicted,
                measured / predicted);
    EXPECT_NEAR(measured / predicted, 1.0, 1e-3) << "k/m = " << stiffness / mass;
  }
}

// Midpoint Euler-Cromer (kick-drift-kick) has symplectic Euler's limit, w h < 2: its step on
// x'' = -w^2 x has the amplification matrix [[1 - a/2, h], [-(w^2 h)(1 - a/4), 1 - a/2]] with
// a = (wh)^2, determinant 1 and trace 2 - a, so its eigenvalues stay on the unit circle (the
// energy error stays bounded: no growth at any step below the limit) while |2 - a| < 2.
TEST(IntegratorStability, MidpointEulerCromerLimitOfOneSpringIsTwoSqrtMassOverStiffness) {
  for (const auto& [mass, stiffness] : {std::pair{1.0, 1.0}, {1e-3, 10.0}, {10.0, 1e5}, {1e-4, 1e4}}) {
    Cloth cloth = spring_oscillator(mass, stiffness);
    cloth.state.x(0, 1) += 1e-6;
    const double predicted = 2.0 * std::sqrt(mass / stiffness);
    const double measured =
        largest_stable_step(cloth, 0.9 * predicted, 1.1 * predicted, 20000, Scheme::midpoint_euler_cromer);
    std::printf("midpoint Euler-Cromer, k/m = %.0e: h_max / (2 sqrt(m/k)) = %.6f\n", stiffness / mass,
                measured / predicted);
    EXPECT_NEAR(measured / predicted, 1.0, 1e-3) << "k/m = " << stiffness / mass;
  }
}

// Undamped, at half its limit, the spring's energy stays within a bounded band over 1e5 steps
// (the modified energy of a symplectic scheme), where the explicit midpoint rule grows by
// sqrt(1 + (wh)^4 / 4) a step.
TEST(IntegratorStability, MidpointEulerCromerKeepsAnUndampedSpringsEnergyBounded) {
  const double mass = 0.01, stiffness = 100.0, omega = std::sqrt(stiffness / mass);
  const double h = 1.0 / omega;  // w h = 1: half the limit
  const auto energy = [&](const Cloth& c) {
    const double stretch = (c.state.x.col(1) - c.state.x.col(0)).norm() - 1.0;
    return 0.5 * mass * c.state.v.col(1).squaredNorm() + 0.5 * stiffness * stretch * stretch;
  };
  Cloth leapfrog = spring_oscillator(mass, stiffness), runge_kutta = leapfrog;
  leapfrog.state.x(0, 1) += 0.01;
  runge_kutta.state.x(0, 1) += 0.01;
  const double initial = energy(leapfrog);
  ExplicitWorkspace workspace;
  double worst = 0.0;
  for (int k = 0; k < 100000; ++k) {
    midpoint_euler_cromer_step(leapfrog, Vec3::Zero(), h, workspace);
    worst = std::max(worst, std::abs(energy(leapfrog) / initial - 1.0));
    if (k < 200) explicit_midpoint_step(runge_kutta, Vec3::Zero(), h, workspace);
  }
  std::printf("w h = 1: midpoint Euler-Cromer worst |E/E0 - 1| over 1e5 steps %.3f; explicit midpoint after 200 "
              "steps E/E0 = %.3g\n", worst, energy(runge_kutta) / initial);
  EXPECT_LT(worst, 0.5);  // the band of the modified energy at w h = 1 (1/(1 - (wh)^2/4) - 1 = 1/3)
  EXPECT_GT(energy(runge_kutta) / initial, 1e5);  // sqrt(1.25)^400 = 1.5e19 in amplitude squared
}

// The limit of a cloth is 2/omega_max with omega_max^2 the largest eigenvalue of M^-1 K.
void expect_cloth_limit_matches_largest_frequency(const Cloth& rest, const char* name) {
  Cloth cloth = rest;
  perturb(cloth, 1e-6, 3);
  const double omega_max = test::largest_frequency(cloth.model, cloth.model.rest_positions);
  const double predicted = 2.0 / omega_max;
  const double measured = largest_stable_step(cloth, 0.8 * predicted, 1.2 * predicted, 20000);
  // The docs' rule of thumb: 2 sqrt(m_i / k_i) with k_i the summed stiffness at vertex i.
  Eigen::VectorXd summed = Eigen::VectorXd::Zero(cloth.num_vertices());
  for (int s = 0; s < cloth.model.springs.size(); ++s) {
    for (int end = 0; end < 2; ++end) summed[cloth.model.springs.vertices(end, s)] += cloth.model.springs.stiffness[s];
  }
  const double rule_of_thumb = 2.0 * (cloth.model.mass.array() / summed.array()).sqrt().minCoeff();
  std::printf("%s: omega_max = %.4e rad/s, h_max = %.6e, 2/omega_max = %.6e, ratio %.5f; 2 sqrt(m/k_sum) = %.4e\n",
              name, omega_max, measured, predicted, measured / predicted, rule_of_thumb);
  EXPECT_NEAR(measured / predicted, 1.0, 0.01);
}

TEST(IntegratorStability, SymplecticEulerLimitOfSmallClothIsTwoOverLargestFrequency) {
  expect_cloth_limit_matches_largest_frequency(
      test::spring_grid_cloth(5, 0.4, 0.01, test::spring_params(100.0, 40.0, 10.0)), "5x5 cloth");
}

// An 8x8 cloth whose vertex masses are spread log-uniformly over 1e-3..1e3 times 10 g.
Cloth mixed_mass_cloth() {
  Cloth cloth = test::spring_grid_cloth(8, 0.7, 0.01, test::spring_params(1000.0, 400.0, 100.0));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> exponent(-3.0, 3.0);
  Eigen::VectorXd mass(cloth.num_vertices());
  for (int i = 0; i < mass.size(); ++i) mass[i] = 0.01 * std::pow(10.0, exponent(rng));
  mass[0] = 1e-5;    // both extremes present
  mass[9] = 10.0;
  test::set_masses(cloth.model, mass);
  return cloth;
}

TEST(IntegratorStability, SymplecticEulerLimitWithMassRatiosOfOneMillion) {
  const Cloth cloth = mixed_mass_cloth();
  EXPECT_GE(cloth.model.mass.maxCoeff() / cloth.model.mass.minCoeff(), 0.999e6);
  expect_cloth_limit_matches_largest_frequency(cloth, "mass ratio 1e6 cloth");
}

// Implicit Euler (Cholesky, h = 1/30 s) on a cloth pinned at two corners: every Newton solve ends
// with a residual a million times below the larger of its starting residual and the cloth's weight
// (once the cloth has settled a step starts at equilibrium, where round-off bounds the reduction),
// and with mass damping the cloth comes to static equilibrium.
// (With compressed springs the PSD-projected Hessian is inexact and Newton only converges
// linearly, so with extreme mass ratios a few steps stop at the iteration cap or where the
// line search can no longer resolve a decrease of the incremental potential in round-off.)
void expect_implicit_settles(Cloth cloth, int steps, const char* name) {
  const Vec3 gravity(0.0, -9.81, 0.0);
  const int n = cloth.model.grid_nx;
  cloth.model.inverse_mass[(n - 1) * n] = cloth.model.inverse_mass[n * n - 1] = 0.0;
  cloth.model.mass_damping = 2.0;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings;
  settings.linear_solver = LinearSolverKind::cholesky;
  settings.newton_tolerance = 1e-6;
  settings.max_newton_iterations = 100;
  const double h = 1.0 / 30.0;
  int unconverged = 0, most_iterations = 0;
  double worst_reduction = 0.0;
  double peak_kinetic = 0.0, kinetic = 0.0;
  const double weight = cloth.model.mass.sum() * gravity.norm();
  for (int k = 0; k < steps; ++k) {
    const NewtonReport& report = solver.step(cloth, gravity, h, settings);
    unconverged += !report.converged;
    most_iterations = std::max(most_iterations, report.newton_iterations);
    const double scale = std::max(report.gradient_norms.front(), weight);
    worst_reduction = std::max(worst_reduction, report.gradient_norms.back() / scale);
    ASSERT_TRUE(cloth.state.x.allFinite()) << name << ", step " << k;
    kinetic = 0.5 * (cloth.state.v.colwise().squaredNorm() * cloth.model.mass)(0);
    peak_kinetic = std::max(peak_kinetic, kinetic);
  }
  // Static equilibrium: every free vertex's net force is tiny next to its weight.
  Positions force(3, cloth.num_vertices());
  compute_forces(cloth.model, gravity, cloth.state.x, Positions::Zero(3, cloth.num_vertices()), force);
  // Newton's residual bounds each vertex's unbalanced force by its own mass (h |g_i| / m_i below
  // the tolerance), but the steps that stop at the cap or on round-off (above) leave more, and next
  // to the weight of the lightest vertex (1e6 times lighter than the heaviest) that is not small,
  // so the per-vertex balance is checked at 1e-2 and the whole cloth's at 1e-5.
  double worst_balance = 0.0, net_force = 0.0;
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    if (cloth.model.inverse_mass[i] == 0.0) continue;
    worst_balance = std::max(worst_balance, force.col(i).norm() / (cloth.model.mass[i] * gravity.norm()));
    net_force += force.col(i).squaredNorm();
  }
  net_force = std::sqrt(net_force);
  std::printf(
      "%s: most Newton iterations %d, unconverged %d of %d, worst r_end/r_0 %.1e, final/peak kinetic %.2e, "
      "worst |f|/(m g) %.2e, |f| / (M g) %.2e\n",
      name, most_iterations, unconverged, steps, worst_reduction, kinetic / peak_kinetic, worst_balance,
      net_force / weight);
  EXPECT_LT(worst_reduction, 1e-6) << name;
  EXPECT_LE(unconverged, steps / 50) << name;
  EXPECT_LT(kinetic, 1e-8 * peak_kinetic) << name;
  EXPECT_LT(worst_balance, 1e-2) << name;
  EXPECT_LT(net_force / weight, 1e-5) << name;
  // Bounded: nothing fell further than the cloth's size stretched three-fold below the pins.
  EXPECT_GT(cloth.state.x.row(1).minCoeff(), -3.0 * (cloth.model.rest_positions.row(0).maxCoeff() -
                                                     cloth.model.rest_positions.row(0).minCoeff()));
}

TEST(IntegratorStability, ImplicitEulerSettlesWithMassRatiosOfOneMillion) {
  expect_implicit_settles(mixed_mass_cloth(), 300, "mass ratio 1e6");
}

// A 6x6 cloth whose fourth column is moved to within 1e-6 m of the third (lattice spacing 0.1 m):
// the triangles between them have aspect ratio 1e-5 and the springs across them rest lengths ~1e-6.
Cloth squashed_column_cloth() {
  const int n = 6;
  const SpringStiffness params = test::spring_params(200.0, 80.0, 20.0);
  Cloth cloth = test::spring_grid_cloth(n, 0.5, 0.01, params);
  Positions& x = cloth.model.rest_positions;
  for (int j = 0; j < n; ++j) x(0, j * n + 3) = x(0, j * n + 2) + 1e-6;
  cloth.model.springs = make_lattice_springs(n, n, GridTriangulation::alternating, x, params);
  cloth.state.x = x;
  return cloth;
}

TEST(IntegratorStability, ImplicitEulerSettlesWithNearlyDegenerateTriangles) {
  const Cloth cloth = squashed_column_cloth();
  EXPECT_LT(cloth.model.springs.rest_length.minCoeff(), 1.1e-6);
  expect_implicit_settles(cloth, 300, "degenerate triangles");
}

TEST(IntegratorStability, ExplicitIntegratorsStayFiniteWithNearlyDegenerateTriangles) {
  Cloth start = squashed_column_cloth();
  start.model.inverse_mass[30] = start.model.inverse_mass[35] = 0.0;
  const double h = 0.5 * 2.0 / test::largest_frequency(start.model, start.model.rest_positions);
  const Vec3 gravity(0.0, -9.81, 0.0);
  // Symplectic Euler at half its limit, and midpoint at a quarter, swing for 1 s without blowing up.
  Cloth symplectic = start, midpoint = start;
  ExplicitWorkspace workspace;
  const int steps = static_cast<int>(std::ceil(1.0 / h));
  for (int k = 0; k < steps; ++k) symplectic_euler_step(symplectic, gravity, h);
  for (int k = 0; k < 2 * steps; ++k) explicit_midpoint_step(midpoint, gravity, 0.5 * h, workspace);
  for (const Cloth* cloth : {&symplectic, &midpoint}) {
    EXPECT_TRUE(cloth->state.x.allFinite());
    // Bounded: the 0.5 m cloth stays within 2 m of its pins.
    EXPECT_LT((cloth->state.x.colwise() - cloth->state.x.col(30)).colwise().norm().maxCoeff(), 2.0);
  }
}

// A free 5x5 cloth (no pins) with uneven masses, its springs stretched and shaken, spring
// damping on: internal forces cancel in pairs, so only gravity changes the momentum.
Cloth shaken_free_cloth() {
  Cloth cloth = test::spring_grid_cloth(5, 0.4, 0.01, test::spring_params(100.0, 40.0, 10.0, 0.05));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd mass(cloth.num_vertices());
  for (int i = 0; i < mass.size(); ++i) mass[i] = 0.01 * std::pow(2.0, unit(rng));
  test::set_masses(cloth.model, mass);
  perturb(cloth, 0.02, 6);
  for (int i = 0; i < cloth.num_vertices(); ++i) cloth.state.v.col(i) = Vec3(unit(rng), unit(rng), unit(rng));
  return cloth;
}

TEST(IntegratorStability, FreeFallChangesMomentumByExactlyMassTimesGravityTimesTime) {
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 5e-4;
  const int steps = 400;
  ExplicitWorkspace workspace;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings cholesky;
  cholesky.linear_solver = LinearSolverKind::cholesky;
  const ImplicitEulerSettings conjugate_gradient;
  AdaptiveSettings adaptive;
  adaptive.enabled = true;
  adaptive.tolerance = 1e-5;
  AdaptiveState adaptive_state;
  ClothState trial;
  XpbdSolver xpbd;
  const std::vector<std::pair<const char*, std::function<void(Cloth&)>>> integrators = {
      {"symplectic_euler", [&](Cloth& c) { symplectic_euler_step(c, gravity, h); }},
      {"explicit_midpoint", [&](Cloth& c) { explicit_midpoint_step(c, gravity, h, workspace); }},
      {"implicit_euler (cholesky)", [&](Cloth& c) { solver.step(c, gravity, h, cholesky); }},
      {"implicit_euler (cg)", [&](Cloth& c) { solver.step(c, gravity, h, conjugate_gradient); }},
      {"xpbd", [&](Cloth& c) { xpbd.step(c, gravity, h, XpbdSettings{3, 2}); }},
      {"adaptive symplectic_euler",
       [&](Cloth& c) {
         adaptive_advance(c, IntegratorKind::symplectic_euler, gravity, h, adaptive, adaptive_state, workspace, trial);
       }},
      {"adaptive midpoint",
       [&](Cloth& c) {
         adaptive_advance(c, IntegratorKind::explicit_midpoint, gravity, h, adaptive, adaptive_state, workspace, trial);
       }},
  };
  for (const auto& [name, advance] : integrators) {
    Cloth cloth = shaken_free_cloth();
    adaptive_state = AdaptiveState();
    const Vec3 initial = test::total_momentum(cloth);
    const Vec3 impulse = cloth.model.mass.sum() * gravity * (steps * h);
    double largest_internal = 0.0;  // N, so that the test is not trivially satisfied
    // Implicit Euler's momentum error of a step is h times the sum of the incremental potential's
    // gradient where Newton stopped (the internal forces sum to zero), at most h sqrt(n) |g|.
    double newton_bound = 0.0;
    for (int k = 0; k < steps; ++k) {
      advance(cloth);
      if (std::string(name).find("implicit_euler") == 0) {
        newton_bound += h * std::sqrt(double(cloth.num_vertices())) * solver.last_report().gradient_norms.back();
      }
      Positions force(3, cloth.num_vertices());
      compute_forces(cloth.model, Vec3::Zero(), cloth.state.x, cloth.state.v, force);
      largest_internal = std::max(largest_internal, force.colwise().norm().maxCoeff());
    }
    const double relative = (test::total_momentum(cloth) - initial - impulse).norm() / impulse.norm();
    std::printf("%s: |P(t) - P(0) - M g t| / |M g t| = %.2e (largest internal force %.2f N, weight %.3f N)\n", name,
                relative, largest_internal, cloth.model.mass.maxCoeff() * gravity.norm());
    // Exact to round-off, except that CG's Newton stops at a gradient whose sum is not zero: its
    // error is bounded by newton_bound above (whatever the signs of the gradient's entries; with
    // their random signs the error is far below it), which the Newton tolerance caps: with every
    // h |g_i| / m_i under it, h sqrt(n) |g| <= tolerance sqrt(n sum m_i^2) a step, so over the run
    // bound <= tolerance sqrt(n sum m_i^2) / (sum m_i |gravity| h).
    // XPBD carries velocity as (x - x_prev) / hs, so the round-off of every position update
    // (1e-16 m) is divided by the sub-step: its bound is that round-off over 1,200 sub-steps.
    const bool inexact_solve = std::string(name).find("(cg)") != std::string::npos;
    const bool velocity_from_positions = std::string(name) == "xpbd";
    if (inexact_solve) {
      const double bound = newton_bound / impulse.norm();
      std::printf("  bound from the final Newton gradients: %.2e\n", bound);
      EXPECT_LT(relative, bound + 1e-12) << name;
      const Eigen::VectorXd& mass = cloth.model.mass;
      const double cap = conjugate_gradient.newton_tolerance *
                         std::sqrt(double(mass.size()) * mass.squaredNorm()) /
                         (mass.sum() * gravity.norm() * h);
      std::printf("  the tolerance's cap on that bound: %.2e\n", cap);
      EXPECT_LT(bound, cap) << name;
    } else {
      EXPECT_LT(relative, velocity_from_positions ? 1e-10 : 1e-12) << name;
    }
    EXPECT_GT(largest_internal, 10.0 * cloth.model.mass.maxCoeff() * gravity.norm()) << name;
  }
}

TEST(IntegratorStability, UndampedSymplecticEulerKeepsEnergyWithinOnePercentOver1e5Steps) {
  // A free 4x4 cloth without gravity or damping, stretched 5% and spinning about its normal
  // while its centre is pushed out of plane: energy is kinetic plus spring energy, both >= 0.
  Cloth cloth = test::spring_grid_cloth(4, 0.3, 0.01, test::spring_params(100.0, 40.0, 10.0));
  cloth.state.x *= 1.05;
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    const Vec3 r = cloth.state.x.col(i);
    cloth.state.v.col(i) = 3.0 * Vec3(r.z(), 0.0, -r.x()) + Vec3(0.0, 0.5 * std::exp(-20.0 * r.squaredNorm()), 0.0);
  }
  cloth.state.v.colwise() -= test::total_momentum(cloth) / cloth.model.mass.sum();
  const double omega_max = test::largest_frequency(cloth.model, cloth.model.rest_positions);
  const double h = 0.01 * 2.0 / omega_max;  // 1% of the stability limit
  const auto energy = [&] {
    return 0.5 * (cloth.state.v.colwise().squaredNorm() * cloth.model.mass)(0) +
           spring_energy(cloth.model.springs, cloth.state.x);
  };
  const double initial = energy();
  const int steps = 100000, window = 1000;
  double worst = 0.0, first_mean = 0.0, last_mean = 0.0;
  for (int k = 0; k < steps; ++k) {
    symplectic_euler_step(cloth, Vec3::Zero(), h);
    const double relative = energy() / initial - 1.0;
    worst = std::max(worst, std::abs(relative));
    if (k < window) first_mean += relative / window;
    if (k >= steps - window) last_mean += relative / window;
  }
  std::printf("h = %.3e s (omega_max h = %.2f), %.1f s simulated: worst |E/E0 - 1| = %.2e, mean drift %.2e\n", h,
              omega_max * h, steps * h, worst, last_mean - first_mean);
  EXPECT_TRUE(cloth.state.x.allFinite());
  // The energy error oscillates (amplitude ~ omega h / 2 for each mode) without drifting.
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(std::abs(last_mean - first_mean), 1e-3);
}

}  // namespace
}  // namespace weft
