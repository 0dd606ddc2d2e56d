// The Newton iteration's two largest costs on the peers' drape cloth (scenes/drape_sphere.json at
// n x n vertices, its membrane and hinges, on a wavy sheet so that every term is strained and
// bent): assembling the gradient and the PSD-projected Hessian, and one Hessian-vector product
// (what each CG iteration does). One thread.
//   build/release/bench/weft_bench --benchmark_filter=hessian --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include <omp.h>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
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

BENCHMARK(hessian_assembly)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(hessian_multiply)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace weft
