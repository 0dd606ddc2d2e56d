// Steady-state steps allocate nothing: this executable replaces the C allocator's entry points
// (malloc, calloc, realloc, free: what operator new and Eigen's dynamic matrices both end in)
// with ones that count calls while `counting` is set, runs a drape with implicit Euler,
// self-collision and contact with a sphere until the contacts have settled in, then counts the
// heap allocations of further steps; and the same for the tumble dryer (cloth-cloth contact, a
// moving collider). Its own executable, because the replacement is process-wide.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/implicit_euler.hpp"
#include "sim/world.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};

void count_allocation() {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

// glibc's own allocator under its internal names; a program may replace malloc, calloc, realloc
// and free together (glibc manual, "Replacing malloc").
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* memory, std::size_t size);
void __libc_free(void* memory);

void* malloc(std::size_t size) {
  count_allocation();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  count_allocation();
  return __libc_calloc(count, size);
}
void* realloc(void* memory, std::size_t size) {
  count_allocation();
  return __libc_realloc(memory, size);
}
void free(void* memory) { __libc_free(memory); }
}

namespace weft {
namespace {

// Heap allocations made by the next `steps` steps of the world.
long allocations_in_steps(World& world, int steps) {
  allocations = 0;
  counting = true;
  for (int step = 0; step < steps; ++step) world.step();
  counting = false;
  return allocations.load();
}

class SteadyState : public ::testing::TestWithParam<const char*> {};

TEST_P(SteadyState, DrapeStepsAllocateNothing) {
  // drape_sphere at 16x16, started 2 cm above the sphere so contact comes within a few steps.
  nlohmann::json scene = nlohmann::json::parse(R"({
    "solver": {"integrator": "implicit_euler", "time_step": 0.004166666666666667, "newton": {"tolerance": 1e-3}},
    "cloths": [{"grid": {"size": [2, 2], "resolution": [16, 16], "triangulation": "alternating"},
                "transform": {"translation": [0, 0.52, 0], "rotation_degrees": [-90, 0, 0]},
                "density": 0.2,
                "springs": {"structural": {"stiffness": 0, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                            "bend": {"stiffness": 0, "damping": 0}},
                "membrane": {"young_modulus": 5e6, "poisson_ratio": 0.3, "thickness": 5e-4},
                "bending": {"stiffness": 2e-5}, "mass_damping": 0.1, "thickness": 0.005,
                "self_collision": true}],
    "colliders": [{"type": "sphere", "center": [0, 0, 0], "radius": 0.5}]
  })");
  scene["solver"]["newton"]["linear_solver"] = GetParam();
  World world = build_world(parse_scene(scene, "inline"));
  // Buffers (candidates, contact groups, records) grow to the largest contact set they meet; by
  // 1 s the cloth has settled on the sphere.
  for (int step = 0; step < 240; ++step) world.step();
  ASSERT_GT(world.last_step_stats().contacts, 0) << "the cloth lies on the sphere";
  EXPECT_EQ(allocations_in_steps(world, 20), 0) << "heap allocations in 20 steady-state steps";
}

INSTANTIATE_TEST_SUITE_P(LinearSolvers, SteadyState, ::testing::Values("conjugate_gradient", "cholesky"));

class SteadyStateBarrier : public ::testing::TestWithParam<bool> {};

TEST_P(SteadyStateBarrier, DrapeStepsWithContactInTheSolveAllocateNothing) {
  // drape_sphere at 16x16 with the barrier response (self contact, friction with the sphere),
  // the sphere as its mesh or as a ball: the candidate lists, contact pairs, friction pairs and
  // the Newton tail's region grow to the largest set they meet, then stay.
  std::ifstream file(std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json");
  nlohmann::json scene = nlohmann::json::parse(file);
  scene["cloths"][0]["grid"]["resolution"] = {16, 16};
  scene["cloths"][0]["transform"]["translation"] = {0, 0.52, 0};
  scene["collision"]["response"] = "barrier";
  scene["collision"]["strain_limit"] = 0;
  scene["collision"]["analytic_colliders"] = GetParam();
  World world = build_world(parse_scene(scene, "drape_sphere.json"));
  for (int step = 0; step < 240; ++step) world.step();
  ASSERT_GT(world.last_step_stats().contacts, 0) << "the cloth lies on the sphere";
  EXPECT_EQ(allocations_in_steps(world, 20), 0) << "heap allocations in 20 steady-state steps";
}

INSTANTIATE_TEST_SUITE_P(SphereAsMeshOrBall, SteadyStateBarrier, ::testing::Values(false, true));

TEST(SteadyStateSwitch, StepsThatPutTheHingesBackIntoTheMatrixAllocateNothing) {
  // Implicit Euler without the hinges' Hessian in CG's matrix, going on with it from a step's first
  // iteration (hinges_out_of_matrix_iterations 0): every step switches patterns twice (back at its start).
  nlohmann::json scene = nlohmann::json::parse(R"({
    "gravity": [0, -9.81, 0],
    "solver": {"integrator": "implicit_euler", "time_step": 0.004166666666666667},
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [12, 12]},
      "transform": {"rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "membrane": {"young_modulus": 1e6, "poisson_ratio": 0.3, "thickness": 5e-4},
      "bending": {"stiffness": 1e-5},
      "pins": {"corners": ["top_left", "top_right"]}}],
    "collision": {"enabled": false}})");
  World world = build_world(parse_scene(scene, "inline"));
  Cloth cloth = world.cloths()[0];
  ImplicitEulerSettings settings;
  settings.newton_tolerance = 1e-4;
  settings.bending_hessian_share = 1e9;
  settings.hinges_out_of_matrix_iterations = 0;
  ImplicitEulerSolver solver;
  const Vec3 gravity(0.0, -9.81, 0.0);
  for (int step = 0; step < 10; ++step) solver.step(cloth, gravity, 1.0 / 240.0, settings);
  ASSERT_EQ(solver.last_report().full_matrix_steps, 1);
  allocations = 0;
  counting = true;
  for (int step = 0; step < 10; ++step) solver.step(cloth, gravity, 1.0 / 240.0, settings);
  counting = false;
  EXPECT_EQ(allocations.load(), 0) << "heap allocations in 10 steps that switch patterns";
}

TEST(SteadyStateTumble, TumbleDryerStepsAllocateNothing) {
  // The tumble dryer (four cloths, cloth-cloth contact, a turning drum: a moving collider whose
  // hierarchy is refitted every step) with 12x12 cloths: after 1.5 s of tumbling, 20 more steps.
  std::ifstream file(std::string(WEFT_SOURCE_DIR) + "/scenes/tumble_dryer.json");
  nlohmann::json scene = nlohmann::json::parse(file);
  for (auto& cloth : scene["cloths"]) cloth["grid"]["resolution"] = {12, 12};
  World world = build_world(parse_scene(scene, "tumble_dryer.json"));
  for (int step = 0; step < 360; ++step) world.step();
  ASSERT_GT(world.last_step_stats().contacts, 0) << "the cloths lie in the drum";
  EXPECT_EQ(allocations_in_steps(world, 20), 0) << "heap allocations in 20 tumbling steps";
}

}  // namespace
}  // namespace weft
