#pragma once
// Implicit Euler at the stiff extreme: a cloth with springs of stiffness 1e6 N/m, pinned at two
// corners, falls from flat with one step per frame (h = 1/24 s). It must stay finite and bounded,
// keep its springs near rest length and settle. (Symplectic Euler would need h < ~1e-5 s.)
// Shared by tests/sim/test_stiff_cloth.cpp (small and medium meshes, in every ctest run) and
// tests/large/test_stiff_cloth_large.cpp (100 x 100, ctest label "large").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/stability.hpp"
#include "sim/world.hpp"

namespace weft::test {

inline World stiff_cloth_world(int resolution, int max_newton_iterations) {
  auto document = nlohmann::json::parse(R"({
    "solver": {"integrator": "implicit_euler", "time_step": 0.041666666666666664,
               "newton": {"linear_solver": "cholesky", "tolerance": 1e-4}},
    "fps": 24,
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [20, 20]},
      "transform": {"translation": [0, 1, 0], "rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "mass_damping": 4.0,
      "springs": {"structural": {"stiffness": 1e6, "damping": 0},
                  "shear": {"stiffness": 1e6, "damping": 0},
                  "bend": {"stiffness": 1e6, "damping": 0}},
      "pins": {"corners": ["top_left", "top_right"]}
    }]
  })");
  document["solver"]["newton"]["max_iterations"] = max_newton_iterations;
  document["cloths"][0]["grid"]["resolution"] = {resolution, resolution};
  return build_world(parse_scene(document, "<inline>"));
}

// Runs `frames` one-step frames of the n x n stiff cloth and checks it stayed bounded and settled.
// Returns the steps that ended with Newton at its iteration cap (inexact steps).
inline int expect_bounded_and_settled(int n, int max_newton_iterations, int frames) {
  World world = stiff_cloth_world(n, max_newton_iterations);
  EXPECT_EQ(frame_schedule(24.0, world.settings.time_step).steps_per_frame, 1);
  const Cloth& cloth = world.cloths()[0];
  const Vec3 pin = cloth.state.x.col((n - 1) * n);
  std::vector<double> kinetic;
  int capped_steps = 0;
  for (int frame = 0; frame < frames; ++frame) {
    world.step();
    EXPECT_TRUE(cloth.state.x.allFinite()) << "frame " << frame;
    if (!cloth.state.x.allFinite()) return capped_steps;
    kinetic.push_back(world.energies().kinetic);
    capped_steps += world.last_step_stats().unconverged_steps;
    std::printf("%dx%d frame %2d/%d: kinetic %.3e J, Newton %d, residual %.2e\n", n, n, frame + 1, frames,
                kinetic.back(), world.last_step_stats().newton_iterations, world.last_step_stats().residual);
    std::fflush(stdout);
  }
  // Bounded: every vertex within the cloth's diagonal of a pin, and the pins have not moved.
  EXPECT_EQ(cloth.state.x.col((n - 1) * n), pin);
  EXPECT_LT((cloth.state.x.colwise() - pin).colwise().norm().maxCoeff(), std::sqrt(2.0) * 1.01);
  // Nearly inextensible: no spring stretched by more than 1% of its rest length.
  // (The cloth has springs only, so largest_strain() is the largest spring's |d| / rest_length - 1.)
  EXPECT_FALSE(cloth.model.membrane.enabled());
  EXPECT_LT(largest_strain(world), 0.01);
  // Settling: it fell (kinetic energy rose) and then came to rest over the last half second.
  const double peak = *std::max_element(kinetic.begin(), kinetic.end());
  EXPECT_GT(peak, 0.01);
  EXPECT_LT(*std::max_element(kinetic.end() - 12, kinetic.end()), 1e-3 * peak);
  EXPECT_LT(cloth.state.x.row(1).minCoeff(), 0.5);  // it hangs below the pins
  return capped_steps;
}

}  // namespace weft::test
