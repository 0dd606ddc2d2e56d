// The restricted tail of a Newton solve (physics/newton_tail.hpp): it moves only the free
// vertices near those whose residual is above the tolerance, lowers the incremental potential,
// keeps the whole cloth's gradient exact (checked against a fresh evaluation over every element),
// with contact in the solve too (a pair's vertex outside the region), never evaluates past the
// contact's bound, and inside ImplicitEulerSolver the residual a step reports is the whole cloth's.
#include "physics/newton_tail.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "physics/implicit_euler.hpp"
#include "physics/solve_contact.hpp"
#include "sim/world.hpp"

namespace weft {
namespace {

// A 16x16, 0.3 m membrane cloth with hinges of the given bending model and mass damping, pinned
// at two corners, after `steps` steps of h = 1/240 s swinging down.
Cloth swinging_cloth(int steps, const std::string& bending_model = "dihedral") {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "gravity": [0, -9.81, 0],
    "solver": {"integrator": "implicit_euler", "time_step": 0.004166666666666667,
               "newton": {"tolerance": 1e-4, "max_iterations": 60}},
    "fps": 240,
    "cloths": [{
      "grid": {"size": [0.3, 0.3], "resolution": [16, 16], "triangulation": "alternating"},
      "transform": {"rotation_degrees": [-90, 0, 0]},
      "density": 0.2,
      "membrane": {"young_modulus": 5e6, "poisson_ratio": 0.3, "thickness": 5e-4, "compression_factor": 0.01},
      "bending": {"stiffness": 2e-5},
      "mass_damping": 0.1,
      "thickness": 1e-3,
      "pins": {"corners": ["top_left", "top_right"]}}],
    "collision": {"enabled": false}})");
  scene["cloths"][0]["bending"]["model"] = bending_model;
  World world = build_world(parse_scene(scene, "<inline>"));
  for (int k = 0; k < steps; ++k) world.step();
  return world.cloths()[0];
}

// One step of the cloth solved by global Newton iterations to a residual of 1e-9 m/s; whether
// it converged.
bool converge_step(Cloth& cloth, const Vec3& gravity, double h) {
  ImplicitEulerSolver solver;
  ImplicitEulerSettings tight;
  tight.newton_tolerance = 1e-9;
  tight.restricted_tail_share = 0.0;
  tight.max_newton_iterations = 60;
  return solver.step(cloth, gravity, h, tight).converged;
}

// The incremental potential and its pin-masked gradient over every element, as the solver
// evaluates it.
double full_potential(const ClothModel& model, const Vec3& gravity, double h, const Positions& x_start,
                      const Positions& x_hat, const Positions& x, Positions& gradient) {
  gradient.setZero(3, x.cols());
  const HessianStencils none;
  double value = evaluate_mass_quadratic(model.mass, 1.0 / (h * h), x, x_hat, &gradient, nullptr);
  value += evaluate_potential(model, gravity, x, &gradient, nullptr, none, false);
  value += evaluate_dissipation(model, x_start, x, h, &gradient, nullptr, none);
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (model.inverse_mass[i] == 0.0) gradient.col(i).setZero();
  }
  return value;
}

class NewtonTailForBending : public testing::TestWithParam<std::string> {};

TEST_P(NewtonTailForBending, FinishesALocalResidualMovingOnlyItsRegionAndKeepsTheGradientExact) {
  Cloth cloth = swinging_cloth(12, GetParam());
  const ClothModel& model = cloth.model;
  ASSERT_TRUE(NewtonTail::supports(model));
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 240.0;
  const double tolerance = 1e-4;
  // The converged step from this state, then two vertices in the middle pushed off it by a
  // fraction of a micrometre: a residual ~100x the tolerance on a few vertices, as a global
  // Newton iteration leaves it near the end of a step.
  const Positions x_start = cloth.state.x;
  const Positions x_hat = x_start + h * cloth.state.v;
  ASSERT_TRUE(converge_step(cloth, gravity, h));
  Positions x = cloth.state.x;
  const int a = 8 * 16 + 7, b = 8 * 16 + 8;
  x.col(a) += Vec3(0.0, 6e-8, 3e-8);
  x.col(b) += Vec3(3e-8, -3e-8, 0.0);
  const Positions pushed = x;

  Positions gradient;
  const double before = full_potential(model, gravity, h, x_start, x_hat, x, gradient);
  const double residual_before = newton_residual(gradient, model.inverse_mass, h);
  ASSERT_GT(residual_before, 10.0 * tolerance);
  ASSERT_LT(residual_before, 1000.0 * tolerance);

  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  NewtonTail tail;
  tail.prepare(model);
  NewtonTailSettings settings;
  settings.tolerance = tolerance;
  settings.largest_share = 0.2;
  const int iterations = tail.iterate(model, gravity, h, x_start, x_hat, nullptr, nullptr, settings, hessian,
                                      stencils, x, gradient, nullptr);
  EXPECT_GE(iterations, 1);

  Positions fresh;
  const double after = full_potential(model, gravity, h, x_start, x_hat, x, fresh);
  EXPECT_LT(after, before);
  const double scale = fresh.colwise().norm().maxCoeff();
  EXPECT_LT((gradient - fresh).colwise().norm().maxCoeff(), 1e-9 * scale) << "the gradient it kept";
  const double residual_after = newton_residual(fresh, model.inverse_mass, h);
  std::printf("residual %.3e -> %.3e m/s in %d restricted iterations\n", residual_before, residual_after,
              iterations);
  EXPECT_LT(residual_after, tolerance);
  int moved = 0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) {
    if (x.col(i) == pushed.col(i)) continue;
    ++moved;
    EXPECT_GT(model.inverse_mass[i], 0.0) << "a pinned vertex moved: " << i;
  }
  EXPECT_GT(moved, 0);
  EXPECT_LT(moved, x.cols() / 2) << "the whole cloth moved, not a region";
}

INSTANTIATE_TEST_SUITE_P(NewtonTail, NewtonTailForBending, testing::Values("dihedral", "quadratic"));

// A contact joining two vertices far apart on the cloth, E = k/2 |x_a - s x_c - r|^2: one pair
// with weights (1, -s), as a self-contact pair joins vertices of distant parts of a cloth. Its
// max_step allows `bound` of every segment; evaluate() counts the points it is asked about that
// lie off the allowed part of the last segment.
class CouplingContact : public SolveContact {
 public:
  int a = 0, c = 0;
  double s = 0.0, k = 0.0;
  Vec3 r = Vec3::Zero();
  double bound = 0.6;
  Positions from, segment;
  int max_steps = 0;
  int off_segment = 0;

  double begin_step(const Positions&, const Positions&, double) override { return 1.0; }
  double max_step(const Positions& x, const Eigen::Ref<const Positions>& dx) override {
    from = x;
    segment = dx;
    ++max_steps;
    return bound;
  }
  double evaluate(const Positions& x, Positions* gradient, ContactBlocks* blocks) override {
    // The distance of x from the segment's allowed part, from + [0, bound] dx.
    const double length2 = segment.squaredNorm();
    const double t =
        length2 > 0.0 ? std::clamp((x - from).cwiseProduct(segment).sum() / length2, 0.0, bound) : 0.0;
    const double off = (x - from - t * segment).cwiseAbs().maxCoeff();
    if (off > 1e-15 + 1e-9 * segment.cwiseAbs().maxCoeff()) ++off_segment;
    const Vec3 d = x.col(a) - s * x.col(c) - r;
    if (gradient != nullptr) {
      gradient->col(a) += k * d;
      gradient->col(c) -= s * k * d;
    }
    if (blocks != nullptr) {
      blocks->clear();
      blocks->vertices.push_back({a, c, -1, -1});
      blocks->weights.push_back({1.0, -s, 0.0, 0.0});
      blocks->blocks.push_back(k * Mat3::Identity());
    }
    return 0.5 * k * d.squaredNorm();
  }
  double evaluate_moving(const Positions& x, const std::vector<char>& moving, Positions* gradient,
                         ContactBlocks* blocks) override {
    if (blocks != nullptr) blocks->clear();
    return moving[a] || moving[c] ? evaluate(x, gradient, blocks) : 0.0;
  }
  double last_potential() const override { return 0.0; }
  const SolveContactReport& report() const override { return report_; }

 private:
  SolveContactReport report_;
};

TEST(NewtonTail, WithContactKeepsThePartnersGradientExactAndStaysWithinTheContactsBound) {
  Cloth cloth = swinging_cloth(12);
  const ClothModel& model = cloth.model;
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 240.0;
  const double tolerance = 1e-4;
  const Positions x_start = cloth.state.x;
  const Positions x_hat = x_start + h * cloth.state.v;
  ASSERT_TRUE(converge_step(cloth, gravity, h));
  Positions x = cloth.state.x;
  const Positions converged = x;

  // The pair pulls vertex a (mid-cloth) with a residual 50x the tolerance, and its partner c (a
  // free corner far away, a quarter of a's mass) with s = 0.001 of it: 0.1x the tolerance, so c
  // is not in the region around a while its gradient changes with every move of a.
  CouplingContact contact;
  contact.a = static_cast<int>(x.cols() / 2);
  contact.c = 0;
  ASSERT_GT(model.inverse_mass[contact.c], 0.0);
  contact.s = 0.001;
  contact.k = model.mass[contact.a] / (h * h);
  const double pull = 50.0 * tolerance * model.mass[contact.a] / (h * contact.k);
  contact.r = x.col(contact.a) - contact.s * x.col(contact.c) - pull * Vec3(0.6, 0.0, 0.8);
  contact.from = x;
  contact.segment.setZero(3, x.cols());

  const auto fresh_evaluation = [&](const Positions& at, Positions& gradient) {
    double value = full_potential(model, gravity, h, x_start, x_hat, at, gradient);
    Positions contact_gradient = Positions::Zero(3, at.cols());
    const Positions from = contact.from, segment = contact.segment;
    contact.from = at;  // a point of its own (zero) segment
    contact.segment.setZero(3, at.cols());
    value += contact.evaluate(at, &contact_gradient, nullptr);
    contact.from = from;
    contact.segment = segment;
    for (Eigen::Index i = 0; i < at.cols(); ++i) {
      if (model.inverse_mass[i] > 0.0) gradient.col(i) += contact_gradient.col(i);
    }
    return value;
  };
  Positions gradient;
  const double before = fresh_evaluation(x, gradient);
  const Vec3 partner_before = gradient.col(contact.c);
  const double residual_before = newton_residual(gradient, model.inverse_mass, h);
  ASSERT_GT(residual_before, 10.0 * tolerance);
  Positions contact_gradient = Positions::Zero(3, x.cols());
  contact.evaluate(x, &contact_gradient, nullptr);

  SparseHessian hessian;
  HessianStencils stencils;
  prepare_hessian(model, hessian, stencils);
  NewtonTail tail;
  tail.prepare(model);
  NewtonTailSettings settings;
  settings.tolerance = tolerance;
  settings.largest_share = 0.2;
  // One iteration: its region is a's neighbourhood, so c is held, but c's gradient changed.
  settings.max_iterations = 1;
  ASSERT_EQ(tail.iterate(model, gravity, h, x_start, x_hat, nullptr, &contact, settings, hessian, stencils, x,
                         gradient, &contact_gradient),
            1);
  EXPECT_TRUE(x.col(contact.c) == converged.col(contact.c)) << "the partner is outside the first region";
  Positions fresh;
  double after = fresh_evaluation(x, fresh);
  EXPECT_LT(after, before);
  const double exact = 1e-9 * fresh.colwise().norm().maxCoeff();
  EXPECT_LT((gradient - fresh).colwise().norm().maxCoeff(), exact)
      << "the gradient it kept after one iteration";
  EXPECT_GT((fresh.col(contact.c) - partner_before).norm(), 1e3 * exact)
      << "the partner's gradient hardly changed: the check above would not see a stale one";

  // On to the tolerance.
  settings.max_iterations = 30;
  const int iterations = tail.iterate(model, gravity, h, x_start, x_hat, nullptr, &contact, settings, hessian,
                                      stencils, x, gradient, &contact_gradient);
  EXPECT_GE(iterations, 1);
  EXPECT_GE(contact.max_steps, iterations + 1);
  EXPECT_EQ(contact.off_segment, 0) << "evaluated past the contact's bound or off its segment";
  after = fresh_evaluation(x, fresh);
  EXPECT_LT((gradient - fresh).colwise().norm().maxCoeff(), 1e-9 * fresh.colwise().norm().maxCoeff())
      << "the gradient it kept";
  const double residual_after = newton_residual(fresh, model.inverse_mass, h);
  std::printf("residual %.3e -> %.3e m/s in %d restricted iterations\n", residual_before, residual_after,
              iterations + 1);
  EXPECT_LT(residual_after, tolerance);
}

TEST(NewtonTail, TheResidualAStepReportsIsTheWholeCloths) {
  // Steps of the swinging cloth with the tail on: whenever it ran, the residual reported equals
  // one evaluated afresh over every element at the step's end, and a step reported converged is.
  Cloth cloth = swinging_cloth(0);
  const Vec3 gravity(0.0, -9.81, 0.0);
  const double h = 1.0 / 240.0;
  ImplicitEulerSolver solver;
  ImplicitEulerSettings settings;
  settings.newton_tolerance = 1e-4;
  settings.max_newton_iterations = 60;
  settings.restricted_tail_share = 0.2;
  int restricted = 0;
  for (int k = 0; k < 60; ++k) {
    const Positions x_start = cloth.state.x;
    const Positions x_hat = x_start + h * cloth.state.v;
    const NewtonReport& report = solver.step(cloth, gravity, h, settings);
    restricted += report.restricted_iterations;
    Positions gradient;
    full_potential(cloth.model, gravity, h, x_start, x_hat, cloth.state.x, gradient);
    const double residual = newton_residual(gradient, cloth.model.inverse_mass, h);
    EXPECT_NEAR(report.residual, residual, 1e-9 * std::max(residual, 1.0)) << "step " << k;
    if (report.converged) {
      EXPECT_LT(residual, settings.newton_tolerance) << "step " << k;
    }
  }
  std::printf("%d restricted iterations over 60 steps\n", restricted);
  EXPECT_GT(restricted, 0);
}

}  // namespace
}  // namespace weft
