// Weft's supernodal Cholesky (physics/supernodal_cholesky) against CHOLMOD's supernodal LLT
// (SuiteSparse, through Eigen's CholmodSupport) on implicit Euler's Hessian of the drape cloth:
// M/h^2 + the element-wise PSD-projected Hessian of the membrane and hinge bending of an N x N
// cloth (the drape's material, 2 m), bent by a smooth bump so the membrane is not at rest.
// Each solver analyses the pattern once, then factorises and solves `--reps` times; the median
// of each is printed with the relative residual |H x - b| / |b| of the last solve.
//   cmake --build build/release --target weft_cholmod_compare
//   build/release/bench/weft_cholmod_compare [--sizes 32,64,128] [--reps 7] [--threads 1]
// Built only where CHOLMOD is installed (Debian: libsuitesparse-dev).
#include <omp.h>

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/supernodal_cholesky.hpp"
#include "sim/world.hpp"

namespace {

using namespace weft;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The drape's cloth (scenes/drape_sphere.json) on an n x n grid.
Cloth drape_cloth(int n) {
  const std::string resolution = "cloths.0.grid.resolution=[" + std::to_string(n) + "," + std::to_string(n) + "]";
  World world = build_world(load_scene_file(std::string(WEFT_SOURCE_DIR) + "/scenes/drape_sphere.json", {resolution}));
  Cloth cloth = world.cloths()[0];
  // A smooth bump and a small shear, so membrane and hinges are strained.
  for (int i = 0; i < cloth.num_vertices(); ++i) {
    auto p = cloth.state.x.col(i);
    const double r2 = p.x() * p.x() + p.z() * p.z();
    p.y() += 0.3 * std::exp(-4.0 * r2);
    p.x() *= 0.98 + 0.01 * p.z();
  }
  return cloth;
}

struct Timing {
  double analyze = 0.0, factorize = 0.0, solve = 0.0, residual = 0.0;
  long factor_nonzeros = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {32, 64, 128};
  int reps = 7, threads = 1;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--sizes") == 0 && a + 1 < argc) {
      sizes.clear();
      std::stringstream list(argv[++a]);
      for (std::string item; std::getline(list, item, ',');) sizes.push_back(std::stoi(item));
    } else if (std::strcmp(argv[a], "--reps") == 0 && a + 1 < argc) {
      reps = std::max(1, std::stoi(argv[++a]));
    } else if (std::strcmp(argv[a], "--threads") == 0 && a + 1 < argc) {
      threads = std::max(1, std::stoi(argv[++a]));
    } else {
      std::fprintf(stderr, "usage: %s [--sizes 32,64,128] [--reps 7] [--threads 1]\n", argv[0]);
      return 2;
    }
  }
  omp_set_num_threads(threads);
  Eigen::setNbThreads(threads);
  std::printf("solver,n,unknowns,factor_nonzeros,analyze_ms,factorize_ms,solve_ms,relative_residual\n");
  for (const int n : sizes) {
    const Cloth cloth = drape_cloth(n);
    SparseHessian hessian;
    HessianStencils stencils;
    prepare_hessian(cloth.model, hessian, stencils);
    hessian.set_zero();
    const double h = 1.0 / 240.0;
    evaluate_mass_quadratic(cloth.model.mass, 1.0 / (h * h), cloth.state.x, cloth.state.x, nullptr, &hessian);
    evaluate_potential(cloth.model, Vec3(0.0, -9.81, 0.0), cloth.state.x, nullptr, &hessian, stencils, true);
    hessian.finish_assembly();
    const SparseHessian::Matrix& matrix = hessian.matrix();
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(matrix.rows(), -1.0, 1.0);

    Timing ours, cholmod;
    {
      SupernodalCholesky solver;
      auto start = Clock::now();
      solver.analyze(matrix);
      ours.analyze = seconds_since(start);
      std::vector<double> factorize, solve;
      Eigen::VectorXd x;
      for (int r = 0; r < reps; ++r) {
        start = Clock::now();
        if (!solver.factorize(matrix)) {
          std::fprintf(stderr, "n = %d: Weft's factorisation found the matrix not positive definite\n", n);
          return 1;
        }
        factorize.push_back(seconds_since(start));
        start = Clock::now();
        solver.solve(b, x);
        solve.push_back(seconds_since(start));
      }
      ours.factorize = median(factorize);
      ours.solve = median(solve);
      ours.residual = (matrix * x - b).norm() / b.norm();
      ours.factor_nonzeros = solver.factor_nonzeros();
    }
    {
      // CHOLMOD wants the lower triangle of a column-major matrix.
      const Eigen::SparseMatrix<double, Eigen::ColMajor, int> lower = matrix.triangularView<Eigen::Lower>();
      Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double, Eigen::ColMajor, int>, Eigen::Lower> solver;
      auto start = Clock::now();
      solver.analyzePattern(lower);
      cholmod.analyze = seconds_since(start);
      std::vector<double> factorize, solve;
      Eigen::VectorXd x;
      for (int r = 0; r < reps; ++r) {
        start = Clock::now();
        solver.factorize(lower);
        factorize.push_back(seconds_since(start));
        if (solver.info() != Eigen::Success) {
          std::fprintf(stderr, "n = %d: CHOLMOD's factorisation failed\n", n);
          return 1;
        }
        start = Clock::now();
        x = solver.solve(b);
        solve.push_back(seconds_since(start));
      }
      cholmod.factorize = median(factorize);
      cholmod.solve = median(solve);
      cholmod.residual = (matrix * x - b).norm() / b.norm();
      cholmod.factor_nonzeros = static_cast<long>(solver.cholmod().lnz);
    }
    for (const auto& [name, t] : {std::pair<const char*, Timing>{"weft_supernodal", ours}, {"cholmod_supernodal", cholmod}}) {
      std::printf("%s,%d,%ld,%ld,%.3f,%.3f,%.3f,%.2e\n", name, n, static_cast<long>(matrix.rows()), t.factor_nonzeros,
                  1e3 * t.analyze, 1e3 * t.factorize, 1e3 * t.solve, t.residual);
    }
    std::fflush(stdout);
  }
  return 0;
}
