// One World::step() of each integrator on an n x n grid cloth (n = 32, 64, 128, 256), 1 m wide,
// pinned at two corners, default springs, falling under gravity; with 1 and 2 threads.
//   build/release/bench/weft_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Explicit integrators step at a quarter of their stability limit for the grid (it shrinks as
// 1/n); implicit Euler steps at the scene default 1/600 s with its default CG solve and with the
// supernodal Cholesky solve (implicit_euler_cholesky), XPBD at 1/600 s with its default 4
// sub-steps of one sweep (serial: its threads count changes nothing). The *_no_budget variants
// turn the energy budget off, to show its cost.
#include <benchmark/benchmark.h>

#include <cmath>

#include "io/scene_builder.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

World grid_world(int n, IntegratorKind integrator) {
  ClothDesc cloth;
  cloth.grid_nx = cloth.grid_ny = n;
  cloth.grid_width = cloth.grid_height = 1.0;
  cloth.translation = Vec3(0.0, 1.0, 0.0);
  cloth.rotation_degrees = Vec3(-90.0, 0.0, 0.0);
  cloth.pins.corners = {"top_left", "top_right"};
  SceneDesc scene;
  scene.integrator = integrator;
  scene.cloths.push_back(cloth);
  World world = build_world(scene);
  if (integrator == IntegratorKind::symplectic_euler || integrator == IntegratorKind::midpoint_euler_cromer ||
      integrator == IntegratorKind::explicit_midpoint) {
    // 2 sqrt(m / (2 k_sum)) bounds the limit from below (k_sum: springs pulling on one vertex).
    const double vertex_mass = cloth.density * cloth.grid_width * cloth.grid_height / (n * n);
    const double k_sum = 4.0 * (cloth.structural.stiffness + cloth.shear.stiffness + cloth.bend.stiffness);
    world.settings.time_step = 0.25 * 2.0 * std::sqrt(vertex_mass / (2.0 * k_sum));
  }
  return world;
}

void step_benchmark(benchmark::State& state, IntegratorKind integrator,
                    LinearSolverKind linear_solver = LinearSolverKind::conjugate_gradient, bool energy_budget = true) {
  const int n = static_cast<int>(state.range(0));
  World world = grid_world(n, integrator);
  world.settings.implicit.linear_solver = linear_solver;
  world.settings.energy_budget = energy_budget;
  world.settings.threads = static_cast<int>(state.range(1));
  // A few steps first, so the cloth is moving and the solvers' storage exists.
  for (int k = 0; k < 3; ++k) world.step();
  int newton_iterations = 0;
  for (auto _ : state) {
    world.step();
    newton_iterations += world.last_step_stats().newton_iterations;
  }
  if (!world.cloths()[0].state.x.allFinite()) state.SkipWithError("the cloth diverged");
  const double vertices = static_cast<double>(world.cloths()[0].num_vertices());
  state.counters["vertices"] = vertices;
  state.counters["s_per_vertex"] = benchmark::Counter(
      vertices, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (integrator == IntegratorKind::implicit_euler) {
    state.counters["newton_per_step"] =
        benchmark::Counter(newton_iterations, benchmark::Counter::kAvgIterations);
  }
}

void grid_sizes_and_threads(benchmark::internal::Benchmark* benchmark) {
  for (int threads : {1, 2}) {
    for (int n : {32, 64, 128, 256}) benchmark->Args({n, threads});
  }
  benchmark->ArgNames({"n", "threads"})->Unit(benchmark::kMicrosecond)->UseRealTime();
}

BENCHMARK_CAPTURE(step_benchmark, symplectic_euler, IntegratorKind::symplectic_euler)
    ->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, midpoint_euler_cromer, IntegratorKind::midpoint_euler_cromer)
    ->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, explicit_midpoint, IntegratorKind::explicit_midpoint)->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, implicit_euler, IntegratorKind::implicit_euler)
    ->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, implicit_euler_cholesky, IntegratorKind::implicit_euler,
                  LinearSolverKind::cholesky)
    ->Apply(grid_sizes_and_threads);
// The energy budget's share of a step (sim/energy_ledger.hpp): the two Eulers without it.
BENCHMARK_CAPTURE(step_benchmark, symplectic_euler_no_budget, IntegratorKind::symplectic_euler,
                  LinearSolverKind::conjugate_gradient, false)
    ->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, implicit_euler_no_budget, IntegratorKind::implicit_euler,
                  LinearSolverKind::conjugate_gradient, false)
    ->Apply(grid_sizes_and_threads);
BENCHMARK_CAPTURE(step_benchmark, xpbd, IntegratorKind::xpbd)->Apply(grid_sizes_and_threads);

}  // namespace
}  // namespace weft
