// XPBD (physics/xpbd.hpp): with one sweep per sub-step it converges to the continuous motion at
// first order in the sub-step; its membrane edges carry the membrane's stiffness.
#include "physics/xpbd.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "physics/explicit_midpoint.hpp"
#include "support/spring_cloth.hpp"

namespace weft {
namespace {

const Vec3 gravity(0.0, -9.81, 0.0);

// The swinging spring cloth of test_integrator_convergence.cpp (6x6, 10 g per vertex, two pins).
Cloth swinging_cloth() {
  const int n = 6;
  Cloth cloth = test::spring_grid_cloth(n, 0.5, 0.01, test::spring_params(10.0, 4.0, 1.0));
  cloth.model.inverse_mass[(n - 1) * n] = 0.0;
  cloth.model.inverse_mass[n * n - 1] = 0.0;
  return cloth;
}

TEST(Xpbd, OneSweepPerSubstepConvergesAtFirstOrder) {
  const double duration = 0.25;
  Cloth reference = swinging_cloth();
  ExplicitWorkspace workspace;
  const int reference_steps = 200000;
  for (int k = 0; k < reference_steps; ++k) explicit_midpoint_step(reference, gravity, duration / reference_steps, workspace);

  // 25 steps, refined by sub-steps only.
  const int steps = 25;
  std::vector<double> log_h, log_e;
  for (int substeps : {8, 16, 32, 64}) {
    Cloth cloth = swinging_cloth();
    XpbdSolver xpbd;
    for (int k = 0; k < steps; ++k) xpbd.step(cloth, gravity, duration / steps, XpbdSettings{substeps, 1});
    const double error = (cloth.state.x - reference.state.x).lpNorm<Eigen::Infinity>();
    std::printf("%3d sub-steps: error %.3e m\n", substeps, error);
    log_h.push_back(std::log(duration / (steps * substeps)));
    log_e.push_back(std::log(error));
  }
  const Eigen::Map<const Eigen::VectorXd> lh(log_h.data(), 4), le(log_e.data(), 4);
  const Eigen::VectorXd centred = lh.array() - lh.mean();
  const double slope = centred.dot((le.array() - le.mean()).matrix()) / centred.squaredNorm();
  std::printf("observed order %.3f\n", slope);
  EXPECT_NEAR(slope, 1.0, 0.15);
}

}  // namespace
}  // namespace weft
