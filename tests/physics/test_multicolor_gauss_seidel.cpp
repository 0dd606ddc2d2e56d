// The multicolour symmetric Gauss-Seidel split against dense linear algebra on a small cloth's
// assembled Hessian: the colouring is proper, the two block triangular solves and Eisenstat's
// product are what they claim for the colour order, the same bits on any thread count, and CG
// preconditioned by it reaches the asked residual in fewer iterations than block Jacobi, also
// with a coupling kept out of the pattern.
#include <gtest/gtest.h>
#include <omp.h>

#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/conjugate_gradient.hpp"
#include "physics/multicolor_gauss_seidel.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A resolution x resolution cloth with a stiff membrane and hinges, its projected Hessian plus
// the inertia m / h^2 assembled at a random perturbation of the rest shape (h = 1/240 s).
struct AssembledCloth {
  SparseHessian hessian;
  HessianStencils stencils;
};

void assemble(int resolution, unsigned seed, AssembledCloth& out) {
  auto document = nlohmann::json::parse(R"({
    "cloths": [{
      "grid": {"size": [1, 1], "resolution": [8, 8], "triangulation": "alternating"},
      "density": 0.2,
      "springs": {"structural": {"stiffness": 0}, "shear": {"stiffness": 0}, "bend": {"stiffness": 0}},
      "membrane": {"young_modulus": 5e6, "poisson_ratio": 0.3, "thickness": 5e-4},
      "bending": {"stiffness": 2e-3}
    }]
  })");
  document["cloths"][0]["grid"]["resolution"] = {resolution, resolution};
  const World world = build_world(parse_scene(document, "<inline>"));
  const ClothModel& model = world.cloths()[0].model;
  prepare_hessian(model, out.hessian, out.stencils);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  Positions x = model.rest_positions;
  for (Eigen::Index k = 0; k < x.size(); ++k) x.data()[k] += noise(rng);
  out.hessian.set_zero();
  out.hessian.add_diagonal(240.0 * 240.0, model.mass);
  evaluate_potential(model, Vec3(0.0, -9.81, 0.0), x, nullptr, &out.hessian, out.stencils, /*project=*/true);
  out.hessian.finish_assembly();
}

Eigen::VectorXd random_vector(Eigen::Index size, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::VectorXd v(size);
  for (Eigen::Index k = 0; k < size; ++k) v[k] = unit(rng);
  return v;
}

// D + L and D + U of the colour order, dense: block (a, b) kept when a == b, or when b's colour
// is before (after) a's.
void dense_split(const SparseHessian& hessian, const std::vector<int>& color, Eigen::MatrixXd& lower,
                 Eigen::MatrixXd& upper, Eigen::MatrixXd& diagonal) {
  const Eigen::MatrixXd full = Eigen::MatrixXd(hessian.matrix());
  const int n = hessian.num_vertices();
  lower = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  upper = lower;
  diagonal = lower;
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) {
      const auto block = full.block<3, 3>(3 * a, 3 * b);
      if (a == b) {
        diagonal.block<3, 3>(3 * a, 3 * b) = block;
        lower.block<3, 3>(3 * a, 3 * b) = block;
        upper.block<3, 3>(3 * a, 3 * b) = block;
      } else if (color[b] < color[a]) {
        lower.block<3, 3>(3 * a, 3 * b) = block;
      } else {
        upper.block<3, 3>(3 * a, 3 * b) = block;
      }
    }
  }
}

TEST(MulticolorGaussSeidel, ColoursThePatternProperly) {
  AssembledCloth cloth;
  assemble(9, 1, cloth);
  MulticolorGaussSeidel gauss_seidel;
  gauss_seidel.prepare(cloth.hessian);
  const std::vector<int> color = gauss_seidel.colors();
  const SparseHessian::Matrix& matrix = cloth.hessian.matrix();
  ASSERT_EQ(static_cast<int>(color.size()), cloth.hessian.num_vertices());
  int blocks_between_vertices = 0;
  for (int a = 0; a < cloth.hessian.num_vertices(); ++a) {
    ASSERT_GE(color[a], 0);
    ASSERT_LT(color[a], gauss_seidel.num_colors());
    for (SparseHessian::Matrix::InnerIterator it(matrix, 3 * a); it; ++it) {
      const int b = static_cast<int>(it.col()) / 3;
      if (b == a) continue;
      ++blocks_between_vertices;
      EXPECT_NE(color[a], color[b]) << "vertices " << a << " and " << b << " share a block";
    }
  }
  EXPECT_GT(blocks_between_vertices, 0);
  // The membrane's and the hinges' stencils: more than 3 colours, few enough to keep each large.
  EXPECT_GT(gauss_seidel.num_colors(), 3);
  EXPECT_LE(gauss_seidel.num_colors(), 12);
}

TEST(MulticolorGaussSeidel, SolvesAndEisenstatProductMatchDenseAlgebraOnAnyThreadCount) {
  AssembledCloth cloth;
  assemble(9, 2, cloth);
  MulticolorGaussSeidel gauss_seidel;
  gauss_seidel.prepare(cloth.hessian);
  Eigen::MatrixXd lower, upper, diagonal;
  dense_split(cloth.hessian, gauss_seidel.colors(), lower, upper, diagonal);
  const Eigen::MatrixXd full = Eigen::MatrixXd(cloth.hessian.matrix());
  const Eigen::Index size = full.rows();
  const Eigen::VectorXd w = random_vector(size, 3);
  const Eigen::VectorXd p = random_vector(size, 4);
  // C p = (D + L)^-1 H (D + U)^-1 p, densely.
  const Eigen::VectorXd expected_t = upper.partialPivLu().solve(p);
  const Eigen::VectorXd expected_q = lower.partialPivLu().solve(full * expected_t);

  std::vector<Eigen::VectorXd> results;
  const int threads_before = omp_get_max_threads();
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    Eigen::VectorXd u(size), t(size), q(size), transformed_t(size), d(size);
    gauss_seidel.solve_lower(w, u);
    gauss_seidel.solve_upper(w, t);
    const double curvature = gauss_seidel.multiply_transformed(p, transformed_t, q);
    gauss_seidel.multiply_diagonal(w, d);
    const double lower_norm = gauss_seidel.lower_product_squared_norm(w);
    // CG's next direction formed inside the product: p' = z + beta p, then C p', exactly as apart.
    const double beta = 0.37;
    Eigen::VectorXd direction = w, next_t(size), next_q(size);
    const double next_curvature = gauss_seidel.multiply_next_direction(p, beta, direction, next_t, next_q);
    const Eigen::VectorXd formed = p + beta * w;
    Eigen::VectorXd apart_t(size), apart_q(size);
    EXPECT_EQ(next_curvature, gauss_seidel.multiply_transformed(formed, apart_t, apart_q));
    EXPECT_EQ(direction, formed);
    EXPECT_EQ(next_t, apart_t);
    EXPECT_EQ(next_q, apart_q);
    // The diagonal product over a range of vertices, as CG's fused pass takes it.
    Eigen::VectorXd pieces = Eigen::VectorXd::Zero(size);
    const int vertices = static_cast<int>(size / 3);
    gauss_seidel.multiply_diagonal(0, vertices / 3, w, pieces);
    gauss_seidel.multiply_diagonal(vertices / 3, vertices, w, pieces);
    EXPECT_EQ(pieces, d);
    EXPECT_LE((lower * u - w).norm(), 1e-12 * w.norm() * full.norm());
    EXPECT_LE((upper * t - w).norm(), 1e-12 * w.norm() * full.norm());
    EXPECT_LE((transformed_t - expected_t).norm(), 1e-9 * expected_t.norm());
    EXPECT_LE((q - expected_q).norm(), 1e-9 * expected_q.norm());
    EXPECT_NEAR(curvature, p.dot(q), 1e-12 * p.norm() * q.norm());
    EXPECT_LE((d - diagonal * w).norm(), 1e-13 * (diagonal * w).norm());
    EXPECT_NEAR(lower_norm, (lower * w).squaredNorm(), 1e-12 * (lower * w).squaredNorm());
    Eigen::VectorXd all(5 * size + 2);
    all << u, t, transformed_t, q, d, lower_norm, curvature;
    results.push_back(all);
  }
  omp_set_num_threads(threads_before);
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(results[0], results[2]);
}

// A new pattern (another cloth) is noticed: the split is redone, not reused.
TEST(MulticolorGaussSeidel, FollowsANewPattern) {
  AssembledCloth small, large;
  assemble(5, 5, small);
  assemble(7, 6, large);
  MulticolorGaussSeidel gauss_seidel;
  gauss_seidel.prepare(small.hessian);
  gauss_seidel.prepare(large.hessian);
  const Eigen::VectorXd w = random_vector(large.hessian.matrix().rows(), 7);
  Eigen::VectorXd u(w.size());
  gauss_seidel.solve_lower(w, u);
  Eigen::MatrixXd lower, upper, diagonal;
  dense_split(large.hessian, gauss_seidel.colors(), lower, upper, diagonal);
  EXPECT_LE((lower * u - w).norm(), 1e-12 * w.norm() * lower.norm());
}

// CG on `hessian` (plus `coupling` when given) with both preconditioners, each on 1 and 2
// threads: every solve reaches the asked residual of the whole system (checked here on b - A dx),
// the two thread counts give the same bits, and symmetric Gauss-Seidel takes fewer iterations.
void expect_gauss_seidel_beats_block_jacobi(const SparseHessian& hessian, const Eigen::VectorXd& b,
                                            const ConjugateGradientSolver::Coupling* coupling) {
  int iterations[2] = {0, 0};
  const int threads_before = omp_get_max_threads();
  for (const Preconditioner preconditioner :
       {Preconditioner::block_jacobi, Preconditioner::symmetric_gauss_seidel}) {
    std::vector<Eigen::VectorXd> solutions;
    for (const int threads : {1, 2}) {
      omp_set_num_threads(threads);
      ConjugateGradientSolver cg;
      cg.set_preconditioner(preconditioner);
      Eigen::VectorXd dx;
      const ConjugateGradientReport report = cg.solve(hessian, b, dx, 1e-8, 2000, coupling);
      EXPECT_TRUE(report.converged);
      Eigen::VectorXd product = hessian.matrix() * dx;
      if (coupling != nullptr) (*coupling)(dx, product);
      const double residual = (b - product).norm() / b.norm();
      EXPECT_LE(residual, 1.01e-8);
      EXPECT_NEAR(report.relative_residual, residual, 1e-3 * residual);
      iterations[preconditioner == Preconditioner::symmetric_gauss_seidel] = report.iterations;
      solutions.push_back(dx);
    }
    EXPECT_EQ(solutions[0], solutions[1]);
  }
  omp_set_num_threads(threads_before);
  EXPECT_GT(iterations[0], 10);
  EXPECT_LT(iterations[1], 0.75 * iterations[0])
      << "Jacobi " << iterations[0] << ", Gauss-Seidel " << iterations[1];
}

// CG on the stiff cloth's Newton matrix.
TEST(MulticolorGaussSeidel, ConjugateGradientConvergesInFewerIterationsThanBlockJacobi) {
  AssembledCloth cloth;
  assemble(16, 8, cloth);
  expect_gauss_seidel_beats_block_jacobi(cloth.hessian, random_vector(cloth.hessian.matrix().rows(), 9),
                                         nullptr);
}

// The same with a coupling kept out of the pattern, as contact between vertices that share no
// element adds it: pairs (a, b) across the cloth with a PSD block [K, -K; -K, K], K = k n n^T, whose
// diagonal blocks are in the matrix and whose off-diagonal ones CG applies through the coupling.
// Gauss-Seidel sees H alone and still solves H + C in fewer iterations.
TEST(MulticolorGaussSeidel, ConjugateGradientSolvesACoupledSystemInFewerIterationsThanBlockJacobi) {
  AssembledCloth cloth;
  assemble(16, 10, cloth);
  const int n = cloth.hessian.num_vertices();
  struct CouplingPair {
    int a, b;
    Mat3 block;
  };
  std::vector<CouplingPair> pairs;
  const double stiffness = 240.0 * 240.0 * 1e-3;  // about a vertex's m / h^2
  for (int a = 0; a + n / 2 < n; a += 7) {
    const Vec3 normal = Vec3(0.3, 1.0, -0.2).normalized();
    pairs.push_back({a, a + n / 2, stiffness * normal * normal.transpose()});
    cloth.hessian.add_vertex_block(a, pairs.back().block);
    cloth.hessian.add_vertex_block(a + n / 2, pairs.back().block);
  }
  const ConjugateGradientSolver::Coupling coupling = [&](const Eigen::VectorXd& p, Eigen::VectorXd& y) {
    for (const CouplingPair& pair : pairs) {
      y.segment<3>(3 * pair.a) -= pair.block * p.segment<3>(3 * pair.b);
      y.segment<3>(3 * pair.b) -= pair.block * p.segment<3>(3 * pair.a);
    }
  };
  expect_gauss_seidel_beats_block_jacobi(cloth.hessian, random_vector(cloth.hessian.matrix().rows(), 11),
                                         &coupling);
}
}  // namespace
}  // namespace weft
