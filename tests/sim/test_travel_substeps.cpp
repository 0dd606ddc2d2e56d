// solver.max_travel_edges: a step whose start velocities would carry a vertex farther than that
// many of its shortest rest edges runs as the fewest equal sub-steps that do not, the same
// computation as asking for that many sub-steps, and no more sub-steps than needed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A 9 x 9 membrane cloth of 0.8 m (every vertex's shortest rest edge 0.1 m), implicit Euler at
// h = 1/30 s, thrown down at `speed` m/s.
World thrown_cloth(double speed, int substeps, double max_travel_edges) {
  auto document = nlohmann::json::parse(R"({
    "solver": {"integrator": "implicit_euler", "time_step": 0.03333333333333333},
    "fps": 30,
    "cloths": [{
      "grid": {"size": [0.8, 0.8], "resolution": [9, 9]},
      "transform": {"rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "springs": {"structural": {"stiffness": 0}, "shear": {"stiffness": 0}, "bend": {"stiffness": 0}},
      "membrane": {"young_modulus": 1e5, "poisson_ratio": 0.3, "thickness": 5e-4},
      "bending": {"stiffness": 1e-5},
      "mass_damping": 0.1
    }]
  })");
  document["solver"]["substeps"] = substeps;
  document["solver"]["max_travel_edges"] = max_travel_edges;
  World world = build_world(parse_scene(document, "<inline>"));
  Cloth& cloth = world.cloths()[0];
  for (Eigen::Index i = 0; i < cloth.state.v.cols(); ++i) cloth.state.v.col(i) = Vec3(0.0, -speed, 0.0);
  return world;
}

struct TravelRun {
  Positions x;
  Positions v;
  std::vector<int> substeps;  // StepStats::substeps of each step
};

TravelRun run(World world, int steps) {
  TravelRun result;
  for (int k = 0; k < steps; ++k) {
    world.step();
    result.substeps.push_back(world.last_step_stats().substeps);
  }
  result.x = world.cloths()[0].state.x;
  result.v = world.cloths()[0].state.v;
  return result;
}

// At 4 m/s a step would carry every vertex h |v| + h^2 |g| = 0.144 m, 1.44 edges: with a bound of
// one edge that is two sub-steps (and still two after three steps of falling, under 1.8 edges),
// bit for bit the run that asks for two; with a bound of a quarter edge, six.
TEST(TravelSubsteps, AFastStepRunsAsTheFewestSubStepsThatKeepEveryVertexWithinTheBound) {
  const TravelRun bounded = run(thrown_cloth(4.0, 1, 1.0), 3);
  const TravelRun asked = run(thrown_cloth(4.0, 2, 0.0), 3);
  EXPECT_EQ(bounded.substeps, std::vector<int>({2, 2, 2}));
  EXPECT_EQ(asked.substeps, std::vector<int>({2, 2, 2}));
  EXPECT_EQ(bounded.x, asked.x);
  EXPECT_EQ(bounded.v, asked.v);

  const TravelRun finer = run(thrown_cloth(4.0, 1, 0.25), 1);
  const TravelRun asked_six = run(thrown_cloth(4.0, 6, 0.0), 1);
  EXPECT_EQ(finer.substeps, std::vector<int>({6}));
  EXPECT_EQ(finer.x, asked_six.x);
  EXPECT_EQ(finer.v, asked_six.v);
}

// A bound the motion stays within changes nothing: the requested sub-steps, the same bits as
// without it; and a bound asks for more sub-steps only where the requested ones are too few.
TEST(TravelSubsteps, ABoundTheMotionKeepsChangesNothing) {
  const TravelRun loose = run(thrown_cloth(4.0, 1, 100.0), 3);
  const TravelRun plain = run(thrown_cloth(4.0, 1, 0.0), 3);
  EXPECT_EQ(loose.substeps, std::vector<int>({1, 1, 1}));
  EXPECT_EQ(loose.x, plain.x);
  EXPECT_EQ(loose.v, plain.v);

  const TravelRun already = run(thrown_cloth(4.0, 3, 1.0), 2);
  EXPECT_EQ(already.substeps, std::vector<int>({3, 3}));
}

// A velocity no sub-step count can follow (a diverged cloth) takes max_travel_substeps, not more.
TEST(TravelSubsteps, TheCountIsCapped) {
  const TravelRun thrown = run(thrown_cloth(1000.0, 1, 1.0), 1);
  EXPECT_EQ(thrown.substeps, std::vector<int>({max_travel_substeps}));
  EXPECT_TRUE(thrown.x.allFinite());
}

}  // namespace
}  // namespace weft
