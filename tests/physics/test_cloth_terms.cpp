// Taylor tests of a whole cloth with every term on at once: the assembled gradient against the
// summed energy, and the assembled (unprojected) sparse Hessian against the gradient, so the
// per-term kernels, the stencils and the assembly are checked together. Also: the projected
// Hessian is positive semi-definite, and the drag and spring-damping dissipation potential's
// derivatives are right.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>
#include <tuple>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/cloth_terms.hpp"
#include "physics/conjugate_gradient.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A 5x5 grid with springs (and their damping), a plain StVK membrane (compression factor 1,
// so the energy is C2 and the Hessian test is exact), hinge bending in the given model and air drag.
ClothModel every_term_model(const std::string& bending_model = "dihedral") {
  auto document = nlohmann::json::parse(R"({
    "wind": [0.3, -0.2, 1.0],
    "cloths": [{
      "grid": {"size": [1, 0.8], "resolution": [5, 5], "triangulation": "alternating"},
      "density": 0.3,
      "springs": {"structural": {"stiffness": 40, "damping": 0.3},
                  "shear": {"stiffness": 20, "damping": 0.1},
                  "bend": {"stiffness": 5, "damping": 0.05}},
      "membrane": {"young_modulus": 1e4, "poisson_ratio": 0.3, "thickness": 1e-3, "compression_factor": 1},
      "bending": {"stiffness": 1e-2},
      "air_drag": {"normal": 2.0, "tangential": 0.5}
    }]
  })");
  document["cloths"][0]["bending"]["model"] = bending_model;
  World world = build_world(parse_scene(document, "<inline>"));
  return world.cloths()[0].model;
}

Positions perturbed(const Positions& x, double amplitude, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, amplitude);
  Positions y = x;
  for (Eigen::Index k = 0; k < y.size(); ++k) y.data()[k] += noise(rng);
  return y;
}

double dot(const Positions& a, const Positions& b) { return (a.array() * b.array()).sum(); }

Positions times(const SparseHessian& hessian, const Positions& d) {
  Positions out(3, d.cols());
  Eigen::Map<Eigen::VectorXd>(out.data(), out.size()) =
      hessian.matrix() * Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
  return out;
}

// Ratios r(eps/2)/r(eps) of the first-order remainders over `halvings` halvings from eps0.
template <class Remainder>
void expect_second_order(Remainder remainder, double eps0, const char* what) {
  double previous = remainder(eps0);
  for (int k = 1; k <= 4; ++k) {
    const double eps = eps0 / std::pow(2.0, k);
    const double current = remainder(eps);
    EXPECT_NEAR(current / previous, 0.25, 0.03) << what << " at halving " << k << " (" << current << " / " << previous << ")";
    previous = current;
  }
}

TEST(ClothTerms, AssembledPotentialGradientAndHessianTaylorTest) {
  for (const std::string bending_model : {"dihedral", "quadratic"}) {
    SCOPED_TRACE(bending_model);
    const ClothModel model = every_term_model(bending_model);
    ASSERT_TRUE(model.membrane.enabled());
    ASSERT_TRUE(model.bending.enabled());
    ASSERT_GT(model.springs.size(), 0);
    const Vec3 gravity(0.0, -9.81, 0.0);
    SparseHessian hessian;
    HessianStencils stencils;
    prepare_hessian(model, hessian, stencils);
    std::mt19937 rng(5);
    for (int trial = 0; trial < 3; ++trial) {
      const Positions x = perturbed(model.rest_positions, 0.03, rng);
      const Positions d = perturbed(Positions::Zero(3, x.cols()), 1.0, rng);
      Positions gradient = Positions::Zero(3, x.cols());
      hessian.set_zero();
      const double energy =
          evaluate_potential(model, gravity, x, &gradient, &hessian, stencils, /*project=*/false);
      hessian.finish_assembly();
      const Positions hd = times(hessian, d);
      expect_second_order(
          [&](double eps) {
            const Positions y = x + eps * d;
            return std::abs(evaluate_potential(model, gravity, y, nullptr, nullptr, stencils, false) -
                            energy - eps * dot(gradient, d));
          },
          1e-2, "energy against gradient");
      expect_second_order(
          [&](double eps) {
            Positions g = Positions::Zero(3, x.cols());
            evaluate_potential(model, gravity, x + eps * d, &g, nullptr, stencils, false);
            return (g - gradient - eps * hd).norm();
          },
          1e-2, "gradient against Hessian");
    }
  }
}

// The block product the conjugate-gradient solver uses equals the scalar sparse product, and
// is the same bit for bit on one thread and on two.
TEST(ClothTerms, BlockMultiplyEqualsTheSparseProduct) {
  const ClothModel model = every_term_model();
  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  std::mt19937 rng(11);
  const Positions x = perturbed(model.rest_positions, 0.03, rng);
  hessian.set_zero();
  evaluate_potential(model, Vec3(0.0, -9.81, 0.0), x, nullptr, &hessian, stencils, /*project=*/true);
  hessian.finish_assembly();
  const Positions d = perturbed(Positions::Zero(3, x.cols()), 1.0, rng);
  const Eigen::VectorXd in = Eigen::Map<const Eigen::VectorXd>(d.data(), d.size());
  const Eigen::VectorXd expected = hessian.matrix() * in;
  Eigen::VectorXd one_thread(in.size()), two_threads(in.size());
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  hessian.multiply(in, one_thread);
  omp_set_num_threads(2);
  hessian.multiply(in, two_threads);
  omp_set_num_threads(threads_before);
  ASSERT_GT(expected.norm(), 0.0);
  EXPECT_LE((one_thread - expected).norm(), 1e-13 * expected.norm());
  EXPECT_EQ(one_thread, two_threads);
}

// Conjugate gradient on the assembled projected Hessian plus a mass term, with either
// preconditioner: reaches the asked residual, and gives the same bits on one, two and three
// threads (its reductions are summed over fixed chunks in order).
TEST(ClothTerms, ConjugateGradientSolvesAndIsTheSameOnAnyThreadCount) {
  const ClothModel model = every_term_model();
  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  std::mt19937 rng(23);
  const Positions x = perturbed(model.rest_positions, 0.03, rng);
  hessian.set_zero();
  hessian.add_diagonal(240.0 * 240.0, model.mass);
  evaluate_potential(model, Vec3(0.0, -9.81, 0.0), x, nullptr, &hessian, stencils, /*project=*/true);
  hessian.finish_assembly();
  const Positions rhs = perturbed(Positions::Zero(3, x.cols()), 1.0, rng);
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(rhs.data(), rhs.size());
  const int threads_before = omp_get_max_threads();
  for (const Preconditioner preconditioner :
       {Preconditioner::block_jacobi, Preconditioner::symmetric_gauss_seidel}) {
    std::vector<Eigen::VectorXd> solutions;
    for (const int threads : {1, 2, 3}) {
      omp_set_num_threads(threads);
      ConjugateGradientSolver cg;
      cg.set_preconditioner(preconditioner);
      Eigen::VectorXd dx;
      const ConjugateGradientReport report = cg.solve(hessian, b, dx, 1e-8, 1000);
      EXPECT_TRUE(report.converged);
      EXPECT_GT(report.iterations, 3);
      const Eigen::VectorXd residual = b - hessian.matrix() * dx;
      EXPECT_LE(residual.norm(), 1.0001e-8 * b.norm());
      solutions.push_back(dx);
    }
    EXPECT_EQ(solutions[0], solutions[1]);
    EXPECT_EQ(solutions[0], solutions[2]);
  }
  omp_set_num_threads(threads_before);
}

// The inertia and mass-damping form (w/2) |x - c|^2_M: value, gradient w M (x - c) and the
// Hessian's diagonal blocks w m_i I, with the same bits on one, two and three threads.
TEST(ClothTerms, MassQuadraticIsExactAndTheSameOnAnyThreadCount) {
  const int n = 1000;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(0.1, 1.0);
  Eigen::VectorXd mass(n);
  for (int i = 0; i < n; ++i) mass[i] = unit(rng);
  const Positions center = perturbed(Positions::Zero(3, n), 1.0, rng);
  const Positions x = perturbed(center, 0.1, rng);
  const double weight = 240.0 * 240.0;
  double expected = 0.0;
  for (int i = 0; i < n; ++i) expected += 0.5 * weight * mass[i] * (x.col(i) - center.col(i)).squaredNorm();
  SparseHessian hessian;
  hessian.begin_pattern(n);
  hessian.finish_pattern();
  std::vector<double> values;
  const int threads_before = omp_get_max_threads();
  for (const int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    Positions gradient = Positions::Ones(3, n);
    hessian.set_zero();
    values.push_back(evaluate_mass_quadratic(mass, weight, x, center, &gradient, &hessian));
    hessian.finish_assembly();
    for (int i = 0; i < n; ++i) {
      EXPECT_LT((gradient.col(i) - Vec3::Ones() - weight * mass[i] * (x.col(i) - center.col(i))).norm(),
                1e-12 * weight)
          << i;
      EXPECT_LT((hessian.diagonal_block(i) - weight * mass[i] * Mat3::Identity()).norm(), 1e-12 * weight) << i;
    }
  }
  omp_set_num_threads(threads_before);
  EXPECT_NEAR(values[0], expected, 1e-12 * expected);
  EXPECT_EQ(values[0], values[1]);
  EXPECT_EQ(values[0], values[2]);
}

TEST(ClothTerms, DissipationPotentialTaylorTestAndDampingForce) {
  const ClothModel model = every_term_model();
  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  std::mt19937 rng(9);
  const double h = 0.01;
  const Positions x_start = perturbed(model.rest_positions, 0.03, rng);
  const Positions x = x_start + h * perturbed(Positions::Zero(3, x_start.cols()), 0.5, rng);
  const Positions d = perturbed(Positions::Zero(3, x.cols()), 1.0, rng);
  Positions gradient = Positions::Zero(3, x.cols());
  hessian.set_zero();
  const double dissipation = evaluate_dissipation(model, x_start, x, h, &gradient, &hessian, stencils);
  hessian.finish_assembly();
  EXPECT_GT(dissipation, 0.0);
  const Positions hd = times(hessian, d);
  expect_second_order(
      [&](double eps) {
        return std::abs(evaluate_dissipation(model, x_start, x + eps * d, h, nullptr, nullptr, stencils) -
                        dissipation - eps * dot(gradient, d));
      },
      1e-3, "dissipation against its gradient");
  // With the spring directions and triangle normals taken at x_start the dissipation potential
  // is exactly quadratic in x, so the Hessian's remainder is round-off, not O(eps^2).
  for (double eps : {1e-1, 1e-2, 1e-3}) {
    Positions g = Positions::Zero(3, x.cols());
    evaluate_dissipation(model, x_start, x + eps * d, h, &g, nullptr, stencils);
    EXPECT_LT((g - gradient - eps * hd).norm(), 1e-9 * (eps * hd).norm()) << "eps " << eps;
  }
  // Its gradient is minus the damping and drag force at v = (x - x_start) / h. The wind's share
  // of the drag is there at v = 0 too, so compare the change from v = 0.
  Positions gradient_at_rest = Positions::Zero(3, x.cols());
  evaluate_dissipation(model, x_start, x_start, h, &gradient_at_rest, nullptr, stencils);
  Positions force = Positions::Zero(3, x.cols()), force_at_rest = Positions::Zero(3, x.cols());
  compute_forces(model, Vec3::Zero(), x_start, (x - x_start) / h, force);
  compute_forces(model, Vec3::Zero(), x_start, Positions::Zero(3, x.cols()), force_at_rest);
  const Positions damping_force = force - force_at_rest;
  EXPECT_GT(damping_force.norm(), 0.0);
  EXPECT_LT((gradient - gradient_at_rest + damping_force).norm(), 1e-9 * damping_force.norm());
  EXPECT_GT(gradient_at_rest.norm(), 0.0);  // the wind pushes a cloth at rest
}

TEST(ClothTerms, ProjectedHessianIsSymmetricPositiveSemiDefinite) {
  for (const std::string bending_model : {"dihedral", "quadratic"}) {
    SCOPED_TRACE(bending_model);
    const ClothModel model = every_term_model(bending_model);
    SparseHessian hessian;
    HessianStencils stencils;
    prepare_hessian(model, hessian, stencils);
    std::mt19937 rng(17);
    for (int trial = 0; trial < 3; ++trial) {
      const Positions x = perturbed(model.rest_positions, 0.1, rng);  // large: compressed and folded elements
      hessian.set_zero();
      evaluate_potential(model, Vec3::Zero(), x, nullptr, &hessian, stencils, /*project=*/true);
      hessian.finish_assembly();
      const Eigen::MatrixXd dense = Eigen::MatrixXd(hessian.matrix());
      EXPECT_LT((dense - dense.transpose()).norm(), 1e-12 * dense.norm());
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(dense);
      EXPECT_GT(eigen.eigenvalues().minCoeff(), -1e-9 * eigen.eigenvalues().maxCoeff());
    }
  }
}

// A model with the hinge bending term alone (springs and membrane off), in the given model.
ClothModel bending_only_model(const std::string& bending_model) {
  auto document = nlohmann::json::parse(R"({"cloths": [{
      "grid": {"size": [1, 0.8], "resolution": [6, 5], "triangulation": "alternating"},
      "springs": {"structural": {"stiffness": 0, "damping": 0}, "shear": {"stiffness": 0, "damping": 0},
                  "bend": {"stiffness": 0, "damping": 0}},
      "bending": {"stiffness": 1e-2}}]})");
  document["cloths"][0]["bending"]["model"] = bending_model;
  World world = build_world(parse_scene(document, "<inline>"));
  return world.cloths()[0].model;
}

// |H u| / (|H| |u|) for the assembled projected Hessian of the elastic terms at x.
double rigid_leak(const ClothModel& model, const Positions& x, const Positions& motion) {
  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  hessian.set_zero();
  evaluate_potential(model, Vec3::Zero(), x, nullptr, &hessian, stencils, /*project=*/true);
  hessian.finish_assembly();
  const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(motion.data(), motion.size());
  Eigen::VectorXd product(u.size());
  hessian.multiply(u, product);
  const double norm = Eigen::MatrixXd(hessian.matrix()).norm();
  return product.norm() / (norm * u.norm());
}

// Rigid velocities of the vertices at x: a translation t, or a rotation omega about the centroid.
Positions translation(const Positions& x, const Vec3& t) { return t.replicate(1, x.cols()); }
Positions rotation(const Positions& x, const Vec3& omega) {
  const Vec3 centroid = x.rowwise().mean();
  Positions u(3, x.cols());
  for (Eigen::Index i = 0; i < x.cols(); ++i) u.col(i) = omega.cross(Vec3(x.col(i) - centroid));
  return u;
}

// Every Hessian approximation the solver uses (here: element-wise PSD projection, the hinges'
// Gauss-Newton form) leaves rigid motion free: translations at any configuration, rotations at
// the stress-free rest shape, and for the dihedral hinges (whose angle no rigid motion changes)
// rotations at any configuration. A matrix that stiffens rigid motion makes Newton's steps too
// short on small or fine cloth, which then stays frozen in the air. The quadratic model's Hessian
// is exact, not an approximation: constant, so it leaves translations free everywhere and
// rotations at the flat rest shape, where its curvature vectors vanish (elsewhere it is the true
// second derivative along a linearised rotation).
TEST(ClothTerms, ApproximateHessiansLeaveRigidMotionFree) {
  std::mt19937 rng(41);
  const ClothModel dihedral_bending = bending_only_model("dihedral");
  const ClothModel quadratic_bending = bending_only_model("quadratic");
  for (int trial = 0; trial < 3; ++trial) {
    const Vec3 t = Vec3(perturbed(Positions::Zero(3, 1), 1.0, rng).col(0));
    const Vec3 omega = Vec3(perturbed(Positions::Zero(3, 1), 1.0, rng).col(0));
    for (const std::string bending_model : {"dihedral", "quadratic"}) {
      const ClothModel model = every_term_model(bending_model);
      const Positions x = perturbed(model.rest_positions, 0.1, rng);  // compressed and folded elements
      EXPECT_LT(rigid_leak(model, x, translation(x, t)), 1e-12) << bending_model << " " << trial;
      EXPECT_LT(rigid_leak(model, model.rest_positions, rotation(model.rest_positions, omega)), 1e-12)
          << bending_model << " " << trial;
    }
    const Positions folded = perturbed(dihedral_bending.rest_positions, 0.1, rng);
    EXPECT_LT(rigid_leak(dihedral_bending, folded, translation(folded, t)), 1e-12) << trial;
    EXPECT_LT(rigid_leak(dihedral_bending, folded, rotation(folded, omega)), 1e-12) << trial;
    EXPECT_LT(rigid_leak(quadratic_bending, folded, translation(folded, t)), 1e-12) << trial;
    const Positions& rest = quadratic_bending.rest_positions;
    EXPECT_LT(rigid_leak(quadratic_bending, rest, rotation(rest, omega)), 1e-12) << trial;
  }
}

}  // namespace
}  // namespace weft
