// BVH broad phase on randomly crumpled n x n grids: build and swept refit, at 1 and
// 2 threads. Arguments: vertices per side, threads.
//   cmake --build build/release --target weft_bench
//   build/release/bench/weft_bench --benchmark_filter=Bvh --benchmark_repetitions=3
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <random>

#include "collision/bvh.hpp"
#include "core/mesh_generators.hpp"

namespace weft {
namespace {

// Squeezed sideways, folded in waves and jittered by about a spacing: distant parts of the
// cloth come within the margin of each other, as in a crumpled cloth.
struct CrumpledGrid {
  TriangleMesh mesh;
  Positions x_end;  // positions one step later
  double margin;    // a quarter of the grid spacing, as a cloth thickness
};

CrumpledGrid crumpled_grid(int n) {
  CrumpledGrid grid;
  grid.mesh = make_grid(n, n, 1.0, 1.0, GridTriangulation::alternating);
  const double spacing = 1.0 / (n - 1);
  std::mt19937 rng(n);
  std::uniform_real_distribution<double> noise(-0.5 * spacing, 0.5 * spacing);
  Positions& x = grid.mesh.positions;
  for (int v = 0; v < grid.mesh.num_vertices(); ++v) {
    const double px = x(0, v), py = x(1, v);
    x.col(v) = Vec3(0.6 * px + 0.05 * std::sin(9.0 * py), 0.6 * py,
                    0.15 * std::sin(11.0 * px) * std::cos(7.0 * py)) +
               Vec3(noise(rng), noise(rng), noise(rng));
  }
  grid.x_end = x;
  for (int v = 0; v < grid.mesh.num_vertices(); ++v)
    grid.x_end.col(v) += 0.1 * Vec3(noise(rng), noise(rng), noise(rng));
  grid.margin = 0.25 * spacing;
  return grid;
}

void bvh_build(benchmark::State& state) {
  const CrumpledGrid grid = crumpled_grid(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Bvh bvh;
  for (auto _ : state) {
    bvh.build(grid.mesh.positions, grid.x_end, grid.mesh.triangles, grid.margin);
    benchmark::DoNotOptimize(bvh.nodes().data());
  }
  state.counters["triangles"] = grid.mesh.num_triangles();
}

void bvh_refit(benchmark::State& state) {
  const CrumpledGrid grid = crumpled_grid(static_cast<int>(state.range(0)));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  Bvh bvh;
  bvh.build(grid.mesh.positions, grid.mesh.triangles, grid.margin);
  for (auto _ : state) {
    bvh.refit(grid.mesh.positions, grid.x_end, grid.margin);
    benchmark::DoNotOptimize(bvh.nodes().data());
  }
  state.counters["degradation"] = bvh.degradation();
}

void grid_sizes_and_threads(benchmark::internal::Benchmark* benchmark) {
  for (const int n : {32, 64, 128}) {
    for (const int threads : {1, 2}) benchmark->Args({n, threads});
  }
  benchmark->ArgNames({"n", "threads"})->Unit(benchmark::kMicrosecond)->UseRealTime();
}

BENCHMARK(bvh_build)->Name("Bvh/build")->Apply(grid_sizes_and_threads);
BENCHMARK(bvh_refit)->Name("Bvh/refit")->Apply(grid_sizes_and_threads);

}  // namespace
}  // namespace weft
