// Adaptive stepping by step doubling on stiff undamped springs, where the step that the error
// controller must avoid is far above the stability limit: the local error estimate keeps the run
// near a fine fixed-step reference, creates no energy, tightens with the tolerance, and says when
// it cannot meet the tolerance at the smallest step allowed.
#include "physics/adaptive_stepping.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "physics/midpoint_euler_cromer.hpp"
#include "support/spring_cloth.hpp"

namespace weft {
namespace {

const Vec3 gravity(0.0, -9.81, 0.0);
constexpr double duration = 0.5;  // s

// A 12x12 spring cloth 1 m wide with the default scene's stiffnesses (500 / 100 / 10 N/m), no
// damping at all, pinned at two corners of one edge, falling and swinging from rest.
Cloth stiff_undamped_cloth() {
  constexpr int n = 12;
  Cloth cloth = test::spring_grid_cloth(n, 1.0, 0.2 / (n * n), test::spring_params(500.0, 100.0, 10.0));
  cloth.model.inverse_mass[(n - 1) * n] = 0.0;
  cloth.model.inverse_mass[n * n - 1] = 0.0;
  return cloth;
}

double total_energy(const Cloth& cloth) {
  const double kinetic = 0.5 * (cloth.state.v.colwise().squaredNorm() * cloth.model.mass)(0);
  return kinetic + spring_energy(cloth.model.springs, cloth.state.x) -
         (gravity.transpose() * cloth.state.x * cloth.model.mass)(0);
}

struct AdaptiveRun {
  Positions x;
  double largest_energy_gain = 0.0;  // J, above the start's total energy
  double peak_kinetic = 0.0;         // J
  AdaptiveState state;
};

// `frames` calls of adaptive_advance, h_max one frame (1/60 s, 40 times the stability limit).
AdaptiveRun run_adaptive(IntegratorKind kind, double tolerance) {
  Cloth cloth = stiff_undamped_cloth();
  AdaptiveSettings settings;
  settings.enabled = true;
  settings.tolerance = tolerance;
  settings.h_min = 1e-7;
  settings.h_max = 1.0 / 60.0;
  AdaptiveRun run;
  ExplicitWorkspace workspace;
  ClothState trial = cloth.state;
  const double start = total_energy(cloth);
  const int frames = static_cast<int>(duration * 60.0 + 0.5);
  for (int frame = 0; frame < frames; ++frame) {
    adaptive_advance(cloth, kind, gravity, 1.0 / 60.0, settings, run.state, workspace, trial);
    run.largest_energy_gain = std::max(run.largest_energy_gain, total_energy(cloth) - start);
    run.peak_kinetic = std::max(run.peak_kinetic, 0.5 * (cloth.state.v.colwise().squaredNorm() * cloth.model.mass)(0));
  }
  run.x = cloth.state.x;
  return run;
}

const Positions& reference() {
  static const Positions x = [] {
    Cloth cloth = stiff_undamped_cloth();
    ExplicitWorkspace workspace;
    const int steps = 200000;  // h = 2.5e-6 s, w_max h ~ 0.01
    for (int k = 0; k < steps; ++k) midpoint_euler_cromer_step(cloth, gravity, duration / steps, workspace);
    return cloth.state.x;
  }();
  return x;
}

TEST(AdaptiveStepping, StiffUndampedSpringsStayNearTheReferenceAndCreateNoEnergy) {
  const double limit = 2.0 / test::largest_frequency(stiff_undamped_cloth().model, stiff_undamped_cloth().model.rest_positions);
  for (const IntegratorKind kind : {IntegratorKind::symplectic_euler, IntegratorKind::midpoint_euler_cromer}) {
    double previous_error = 0.0;
    for (const double tolerance : {1e-3, 1e-4, 1e-5}) {
      const AdaptiveRun run = run_adaptive(kind, tolerance);
      const double error = (run.x - reference()).lpNorm<Eigen::Infinity>();
      std::printf("%s, tolerance %.0e: %d accepted, %d rejected (stability limit %.2e s), error %.3e m, energy "
                  "gain %.2e J of peak kinetic %.3f J\n",
                  to_string(kind), tolerance, run.state.accepted, run.state.rejected, limit, error,
                  run.largest_energy_gain, run.peak_kinetic);
      SCOPED_TRACE(std::string(to_string(kind)) + " tolerance " + std::to_string(tolerance));
      EXPECT_EQ(run.state.unmet, 0);
      // A symplectic scheme's energy error oscillates within a band that widens towards the
      // stability limit (10% at 1e-3 with midpoint Euler-Cromer); before step doubling this
      // scene went from 0 to ~30 J against a true peak kinetic energy near 1 J.
      EXPECT_LT(run.largest_energy_gain, 0.15 * run.peak_kinetic) << "no energy created";
      // The global error is at most the local errors summed (each under the tolerance), here
      // far less; and within 2 cm whatever the tolerance.
      EXPECT_LT(error, run.state.accepted * tolerance);
      EXPECT_LT(error, 0.02) << "within 2 cm of the reference after 0.5 s";
      if (previous_error > 0.0) {
        EXPECT_LT(error, previous_error) << "a tighter tolerance is closer";
      }
      previous_error = error;
    }
  }
}

TEST(AdaptiveStepping, ATolerancePastReachAtTheSmallestStepIsCounted) {
  // min_step far above the stability limit: the controller cannot shrink enough, and says so.
  Cloth cloth = stiff_undamped_cloth();
  AdaptiveSettings settings;
  settings.enabled = true;
  settings.tolerance = 1e-6;
  settings.h_min = 1e-2;
  settings.h_max = 1e-2;
  AdaptiveState state;
  ExplicitWorkspace workspace;
  ClothState trial = cloth.state;
  adaptive_advance(cloth, IntegratorKind::midpoint_euler_cromer, gravity, 0.05, settings, state, workspace, trial);
  EXPECT_GT(state.unmet, 0);
  EXPECT_EQ(state.accepted, 5);
}

}  // namespace
}  // namespace weft
