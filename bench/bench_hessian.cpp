// The Newton iteration's two largest costs on the peers' drape cloth (scenes/drape_sphere.json at
// n x n vertices, its membrane and hinges, on a wavy sheet so that every term is strained and
// bent): assembling the gradient and the PSD-projected Hessian, and one Hessian-vector product
// (what each CG iteration does), one thread; and a CG solve of 30 iterations with either
// preconditioner on 1 and 2 threads (per solve: the preconditioner's set-up, then 30 iterations).
//   build/release/bench/weft_bench --benchmark_filter='hessian|conjugate' --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
// Run it as weft runs (OMP_WAIT_POLICY=passive GOMP_SPINCOUNT=1000, src/app/openmp_wait_policy.hpp)
// for the 2-thread figures to mean what they do in a simulation.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include <omp.h>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/conjugate_gradient.hpp"
#include "physics/sparse_hessian.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

struct DrapeCloth {
  ClothModel model;
  Positions x;
};

DrapeCloth drape_cloth(int n) {
  const std::string resolution =
      "cloths.0.grid.resolution=[" + std::to_string(n) + "," + std::to_string(n) + "]";
  const World world =
      build_world(load_scene_file(std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json", {resolution}));
  DrapeCloth cloth{world.cloths()[0].model, world.cloths()[0].state.x};
  for (Eigen::Index i = 0; i < cloth.x.cols(); ++i) {
    cloth.x(1, i) += 0.05 * std::sin(7.0 * cloth.x(0, i)) * std::cos(5.0 * cloth.x(2, i));
  }
  return cloth;
}

// The drape's cloth at the benchmark's N with its Hessian's pattern built; one thread.
struct Assembly {
  DrapeCloth cloth;
  SparseHessian hessian;
  HessianStencils stencils;

  explicit Assembly(int n) : cloth(drape_cloth(n)) {
    omp_set_num_threads(1);
    prepare_hessian(cloth.model, hessian, stencils);
  }
};

void hessian_assembly(benchmark::State& state) {
  Assembly assembly(static_cast<int>(state.range(0)));
  const DrapeCloth& cloth = assembly.cloth;
  SparseHessian& hessian = assembly.hessian;
  const HessianStencils& stencils = assembly.stencils;
  Positions gradient(3, cloth.x.cols());
  for (auto _ : state) {
    gradient.setZero();
    hessian.set_zero();
    benchmark::DoNotOptimize(
        evaluate_potential(cloth.model, Vec3(0, -9.81, 0), cloth.x, &gradient, &hessian, stencils, true));
    hessian.finish_assembly();
  }
}

void hessian_multiply(benchmark::State& state) {
  Assembly assembly(static_cast<int>(state.range(0)));
  const DrapeCloth& cloth = assembly.cloth;
  SparseHessian& hessian = assembly.hessian;
  const HessianStencils& stencils = assembly.stencils;
  Positions gradient = Positions::Zero(3, cloth.x.cols());
  evaluate_potential(cloth.model, Vec3(0, -9.81, 0), cloth.x, &gradient, &hessian, stencils, true);
  hessian.finish_assembly();
  Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(gradient.data(), gradient.size());
  Eigen::VectorXd q(p.size());
  for (auto _ : state) {
    hessian.multiply(p, q);
    benchmark::DoNotOptimize(q.data());
  }
  state.counters["blocks"] = static_cast<double>(hessian.matrix().nonZeros()) / 9.0;
}

// The Newton matrix of implicit Euler at the drape's time step (the terms plus M / h^2) and a
// right-hand side (the gradient); 30 CG iterations (a tolerance of 0 is never met).
void conjugate_gradient(benchmark::State& state) {
  Assembly assembly(static_cast<int>(state.range(0)));
  const DrapeCloth& cloth = assembly.cloth;
  SparseHessian& hessian = assembly.hessian;
  Positions gradient = Positions::Zero(3, cloth.x.cols());
  evaluate_potential(cloth.model, Vec3(0, -9.81, 0), cloth.x, &gradient, &hessian, assembly.stencils, true);
  const double h = 1.0 / 240.0;
  hessian.add_diagonal(1.0 / (h * h), cloth.model.mass);
  hessian.finish_assembly();
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(gradient.data(), gradient.size());
  Eigen::VectorXd dx(b.size());
  ConjugateGradientSolver solver;
  solver.set_preconditioner(state.range(2) != 0 ? Preconditioner::symmetric_gauss_seidel
                                                : Preconditioner::block_jacobi);
  omp_set_num_threads(static_cast<int>(state.range(1)));
  int iterations = 0;
  for (auto _ : state) {
    iterations = solver.solve(hessian, b, dx, 0.0, 30).iterations;
    benchmark::DoNotOptimize(dx.data());
  }
  omp_set_num_threads(1);
  state.counters["iterations"] = iterations;
}

void sizes_threads_preconditioners(benchmark::internal::Benchmark* benchmark) {
  benchmark->ArgNames({"n", "threads", "gauss_seidel"});
  for (const int n : {32, 64, 128}) {
    for (const int threads : {1, 2}) {
      for (const int gauss_seidel : {0, 1}) benchmark->Args({n, threads, gauss_seidel});
    }
  }
}

BENCHMARK(hessian_assembly)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(hessian_multiply)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(conjugate_gradient)
    ->Apply(sizes_threads_preconditioners)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

}  // namespace
}  // namespace weft
