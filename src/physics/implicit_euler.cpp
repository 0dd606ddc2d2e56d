#include "physics/implicit_euler.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "physics/bending.hpp"

namespace weft {

namespace {

// Vertex i's share of the residual over h: |g_i| / m_i (0 for pinned vertices).
double vertex_residual_rate(const Positions& gradient, const Eigen::VectorXd& inverse_mass, Eigen::Index i) {
  return gradient.col(i).norm() * inverse_mass[i];
}

}  // namespace

double newton_residual(const Positions& gradient, const Eigen::VectorXd& inverse_mass, double h) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i < gradient.cols(); ++i) {
    largest = std::max(largest, vertex_residual_rate(gradient, inverse_mass, i));
  }
  return h * largest;
}

int vertices_above_tolerance(const Positions& gradient, const Eigen::VectorXd& inverse_mass, double h,
                             double tolerance) {
  int above = 0;
  for (Eigen::Index i = 0; i < gradient.cols(); ++i) {
    above += h * vertex_residual_rate(gradient, inverse_mass, i) > tolerance ? 1 : 0;
  }
  return above;
}

double resting_start_residual(const Vec3& gravity, double h) { return gravity.norm() * h; }

void ImplicitEulerSolver::prepare(const ClothModel& model, bool hinges_in_matrix) {
  num_vertices_ = static_cast<int>(model.rest_positions.cols());
  // Without the hinges, the pattern with them is kept too (full_hessian_), for the steps whose
  // iterations run long (step()); both are built here, so switching allocates nothing.
  hinges_in_matrix_ = hinges_in_matrix;
  prepare_hessian(model, hessian_, stencils_, hinges_in_matrix);
  if (hinges_in_matrix) {
    full_hessian_ = SparseHessian();
    full_stencils_ = HessianStencils{};
  } else {
    prepare_hessian(model, full_hessian_, full_stencils_, true);
  }
  hinges_out_of_matrix_ = !hinges_in_matrix;
  x_start_.resize(3, num_vertices_);
  x_hat_.resize(3, num_vertices_);
  gradient_.resize(3, num_vertices_);
  trial_.resize(3, num_vertices_);
  free_mask_.resize(3 * num_vertices_);
  for (int i = 0; i < num_vertices_; ++i)
    free_mask_.segment<3>(3 * i).setConstant(model.inverse_mass[i] > 0.0);
  rhs_.resize(3 * num_vertices_);
  dx_.resize(3 * num_vertices_);
  trial_step_.resize(3 * num_vertices_);
  gravity_drop_.resize(3 * num_vertices_);
  report_.gradient_norms.reserve(64);
  x_linearized_.resize(3, num_vertices_);
  coupling_ = [this](const Eigen::VectorXd& p, Eigen::VectorXd& y) {
    if (penalty_ != nullptr && penalty_->coupled())
      penalty_->add_coupling_product(x_linearized_, free_mask_, p, y);
    if (contact_coupled_) contact_blocks_.add_coupling_product(free_mask_, p, y);
  };
  zero_motion_.setZero(3, num_vertices_);
  cholesky_ = SupernodalCholesky();
  tail_supported_ = NewtonTail::supports(model);
  if (tail_supported_) tail_.prepare(model);
  prepared_ = true;
}

// Phi(x) = 1/(2h^2) |x - x_hat|^2_M + E(x) + D(x); its gradient (pinned entries zeroed) and,
// if `assemble`, its Hessian M/h^2 + d2E + d2D (d2E projected element-wise to PSD if `project`)
// with pinned rows and columns identity.
double ImplicitEulerSolver::incremental_potential(const ClothModel& model, const Vec3& gravity,
                                                  const Positions& x, double h, Positions* gradient,
                                                  bool assemble, bool project) {
  SparseHessian* hessian = assemble ? &hessian_ : nullptr;
  if (gradient != nullptr) gradient->setZero();
  if (hessian != nullptr) hessian->set_zero();
  double value = evaluate_mass_quadratic(model.mass, 1.0 / (h * h), x, x_hat_, gradient, hessian);
  const double potential = evaluate_potential(model, gravity, x, gradient, hessian, stencils_, project);
  value += potential;
  value += evaluate_dissipation(model, x_start_, x, h, gradient, hessian, stencils_);
  double penalty = 0.0;
  if (penalty_ != nullptr) {
    penalty = penalty_->evaluate(x, gradient, hessian);
    value += penalty;
    if (hessian != nullptr) x_linearized_ = x;
  }
  if (contact_ != nullptr) {
    if (gradient != nullptr) contact_gradient_.setZero(3, x.cols());
    value += contact_->evaluate(x, gradient != nullptr ? &contact_gradient_ : nullptr,
                                hessian != nullptr ? &contact_blocks_ : nullptr);
    if (gradient != nullptr) *gradient += contact_gradient_;
    if (hessian != nullptr) {
      contact_coupled_ = contact_blocks_.assemble(*hessian, /*bound_off_pattern=*/cholesky_in_use_);
    }
  }
  if (gradient != nullptr) {
    last_evaluation_.point = x;
    last_evaluation_.potential = potential;
    last_evaluation_.penalty = penalty;
    last_evaluation_.contact_potential = contact_ != nullptr ? contact_->last_potential() : 0.0;
    if (contact_ != nullptr) {
      last_evaluation_.contact_gradient = contact_gradient_;
    } else {
      last_evaluation_.contact_gradient.resize(3, 0);
    }
    last_evaluation_.gradient = *gradient;
    last_evaluation_valid_ = true;
    Eigen::Map<Eigen::VectorXd>(gradient->data(), gradient->size()).array() *= free_mask_.array();
  }
  if (hessian != nullptr) hessian->finish_assembly();
  return value;
}

const IncrementalPotentialParts* ImplicitEulerSolver::last_evaluation_at(const Positions& x) const {
  // Bitwise: the parts are those of this very point (0.0 and -0.0 need not evaluate alike).
  const bool same_point = last_evaluation_valid_ && last_evaluation_.point.cols() == x.cols() &&
                          std::memcmp(x.data(), last_evaluation_.point.data(),
                                      sizeof(double) * static_cast<size_t>(x.size())) == 0;
  return same_point ? &last_evaluation_ : nullptr;
}

void ImplicitEulerSolver::swap_patterns() {
  hessian_.swap(full_hessian_);
  std::swap(stencils_, full_stencils_);
  hinges_out_of_matrix_ = !hinges_out_of_matrix_;
}

// Solves H dx = rhs_; returns false if the solver failed (for Cholesky: H not positive definite).
bool ImplicitEulerSolver::solve(const ImplicitEulerSettings& settings, double cg_tolerance,
                                const Eigen::VectorXd* cg_guess) {
  const SparseHessian::Matrix& matrix = hessian_.matrix();
  if (settings.linear_solver == LinearSolverKind::cholesky) {
    if (!cholesky_.analyzed()) cholesky_.analyze(matrix);
    if (!cholesky_.factorize(matrix)) return false;
    cholesky_.solve(rhs_, dx_);
    return dx_.allFinite();
  }
  cg_.set_preconditioner(settings.cg_preconditioner);
  const bool coupled =
      (penalty_ != nullptr && penalty_->coupled()) || (contact_ != nullptr && contact_coupled_);
  const ConjugateGradientReport cg = cg_.solve(hessian_, rhs_, dx_, cg_tolerance, settings.max_cg_iterations,
                                               coupled ? &coupling_ : nullptr, cg_guess);
  report_.linear_iterations += cg.iterations;
  return dx_.allFinite() && (cg.iterations > 0 || cg.converged);
}

const NewtonReport& ImplicitEulerSolver::step(Cloth& cloth, const Vec3& gravity, double h,
                                              const ImplicitEulerSettings& settings,
                                              const ContactPenalty* penalty, SolveContact* contact) {
  const ClothModel& model = cloth.model;
  penalty_ = penalty != nullptr && penalty->active() ? penalty : nullptr;
  contact_ = contact;
  contact_coupled_ = false;
  cholesky_in_use_ = settings.linear_solver == LinearSolverKind::cholesky;
  ClothState& state = cloth.state;
  // The hinges' Hessian stays out of CG's matrix while their share of M/h^2 is small (settings'
  // bending_hessian_share). The viewer's sliders change the bending stiffness and the density,
  // and the step h, live: the share is recomputed when they change, and the pattern with it.
  const double mass = model.mass.sum();
  if (!prepared_ || model.bending.stiffness != rate_stiffness_ || mass != rate_mass_) {
    bending_rate_ = bending_stiffness_rate(model.bending, model.rest_positions, model.inverse_mass);
    rate_stiffness_ = model.bending.stiffness;
    rate_mass_ = mass;
  }
  const bool hinges_in_matrix = settings.linear_solver == LinearSolverKind::cholesky ||
                                !(bending_rate_ * h * h < settings.bending_hessian_share);
  if (!prepared_ || num_vertices_ != cloth.num_vertices() || hinges_in_matrix != hinges_in_matrix_) {
    prepare(model, hinges_in_matrix);
  }
  if (!hinges_in_matrix_ && !hinges_out_of_matrix_) swap_patterns();  // each step starts without them
  report_.newton_iterations = 0;
  report_.linear_iterations = 0;
  report_.converged = false;
  report_.residual = 0.0;
  report_.projected_hessians = 0;
  report_.stretched_steps = 0;
  report_.restricted_iterations = 0;
  report_.diverged_stops = 0;
  report_.full_matrix_steps = 0;
  report_.gradient_norms.clear();
  report_.iterations.clear();
  last_evaluation_valid_ = false;  // its x_hat, x_start and penalty were the last step's

  // Inertial predictor; pinned vertices keep their (zero) velocity, so they stay put.
  x_start_ = state.x;
  x_hat_.noalias() = state.x + h * state.v;
  for (int i = 0; i < num_vertices_; ++i) gravity_drop_.segment<3>(3 * i) = h * h * gravity;
  gravity_drop_.array() *= free_mask_.array();
  Positions& x = state.x;
  x = x_hat_;
  // With contact in the solve, the predictor goes only as far along x_hat - x_start as keeps
  // every pair apart; the pins then reach x_hat through the Newton steps.
  if (contact_ != nullptr) {
    pin_targets_ = x_hat_;
    trial_ = x_hat_ - x_start_;
    const double alpha = contact_->begin_step(x_start_, trial_, h);
    if (alpha < 1.0) x.noalias() = x_start_ + alpha * trial_;
  }
  // Every pin on its target (always, without contact in the solve).
  const auto pins_on_target = [&] {
    if (contact_ == nullptr) return true;
    for (int i = 0; i < num_vertices_; ++i) {
      if (model.inverse_mass[i] == 0.0 && !(x.col(i) - pin_targets_.col(i)).isZero(0.0)) return false;
    }
    return true;
  };

  // Whether the Newton step moves a pin (towards its target): such a step is not stretched.
  const auto pins_moving = [&] {
    for (int i = 0; i < num_vertices_; ++i) {
      if (model.inverse_mass[i] == 0.0 && !dx_.segment<3>(3 * i).isZero(0.0)) return true;
    }
    return false;
  };

  // With Cholesky the exact Hessian is tried first: where it is positive definite (near any stable
  // equilibrium) Newton converges quadratically, whereas the projected one, which drops the
  // negative curvature of compressed stiff springs, converges only linearly (ratio 0.85 a step on
  // a 1e6 N/m cloth at h = 1/24). The factorisation tells when it is not; then the projected
  // Hessian is assembled and solved instead. CG cannot tell cheaply, so it always projects.
  const bool exact_first = settings.linear_solver == LinearSolverKind::cholesky;
  // Phi at a point with the gradient and Hessian the next Newton iteration solves with.
  const auto evaluate_for_newton = [&](const Positions& point) {
    return incremental_potential(model, gravity, point, h, &gradient_, /*assemble=*/true, !exact_first);
  };
  double value = evaluate_for_newton(x);
  bool assembled = true;  // the Hessian at x is in hessian_
  const auto gradient_vector = [this] {
    return Eigen::Map<const Eigen::VectorXd>(gradient_.data(), gradient_.size());
  };
  report_.residual = newton_residual(gradient_, model.inverse_mass, h);
  report_.converged = report_.residual < settings.newton_tolerance && pins_on_target();
  const auto record_iteration = [&](double step_scale, int linear_iterations, int restricted) {
    if (!settings.record_iterations) return;
    report_.iterations.push_back(
        {report_.residual,
         vertices_above_tolerance(gradient_, model.inverse_mass, h, settings.newton_tolerance), step_scale,
         linear_iterations, restricted});
  };
  record_iteration(0.0, 0, 0);
  // The iterate with the smallest residual so far. Phi can keep falling by ever smaller amounts
  // while the residual grows by orders of magnitude: a hinge's wing collapsing towards zero height
  // (cheap when the membrane resists compression at 1%), where the angle's gradient grows as
  // 1 / height and the energy stays bounded. Left alone, such a step spends its whole iteration
  // budget there and ends with a residual orders of magnitude above its best. An iteration diverges when its
  // residual is over `diverging_factor` times the best and it lowered Phi by less than
  // `stalled_fraction` of the step's decrease so far; after `diverging_iterations` of them in a
  // row the step stops and returns the best iterate, unconverged. (The residual alone is no merit
  // function: a stiff step's first iterates may raise it while Phi falls a lot.)
  constexpr int diverging_iterations = 3;
  constexpr double diverging_factor = 100.0;
  constexpr double stalled_fraction = 1e-3;
  best_x_ = x;
  double best_residual = report_.residual;
  const double start_value = value;
  int diverging = 0;
  double best_value = value;
  double cg_tolerance = std::max(settings.cg_tolerance, settings.cg_initial_tolerance);
  bool use_tail = tail_supported_ && (penalty_ == nullptr || !penalty_->coupled()) && !exact_first &&
                  settings.restricted_tail_share > 0.0;
  // A step whose tail runs keep ending above the best residual so far is stalled where the tail
  // cannot help (a global iteration cut to a sliver of its step, then the tail's region undone by
  // the next): after this many such runs in a row the step goes on without the tail.
  constexpr int tail_runs_without_progress = 3;
  int tail_runs_behind = 0;
  NewtonTailSettings tail_settings;
  tail_settings.tolerance = settings.newton_tolerance;
  tail_settings.largest_share = settings.restricted_tail_share;
  // Every step takes at least one iteration, even from a start already within the tolerance. The
  // inertial predictor is no neutral guess: its residual is h times the acceleration the step has
  // to add (|g| h in free fall, less the damping), and accepting it drops that acceleration, the
  // same way every step. With the tolerance close to |g| h, a falling cloth would meet it at the
  // predictor and glide at constant speed, every step "converged" with no iteration
  // (ImplicitEuler.AFallingClothKeepsAcceleratingWithAToleranceJustBelowGravitysPull). One
  // iteration makes such a step exact (free fall is linear).
  for (int iteration = 0;
       iteration < settings.max_newton_iterations && (iteration == 0 || !report_.converged); ++iteration) {
    report_.gradient_norms.push_back(gradient_vector().norm());
    const int linear_before = report_.linear_iterations;
    // A step still unconverged after hinges_out_of_matrix_iterations without the hinges goes on with them:
    // where the cloth folds or slides off an edge the matrix without them can stall Newton.
    if (hinges_out_of_matrix_ && iteration == settings.hinges_out_of_matrix_iterations) {
      swap_patterns();
      ++report_.full_matrix_steps;
      assembled = false;
    }
    if (!assembled) evaluate_for_newton(x);  // the last step predicted convergence and was wrong
    if (iteration > 0) {
      const double ratio = report_.gradient_norms[iteration] / report_.gradient_norms[iteration - 1];
      cg_tolerance = std::clamp(ratio * ratio, settings.cg_tolerance, settings.cg_initial_tolerance);
    }
    rhs_ = -gradient_vector();
    // The first solve of a step starts CG from the best multiple of the drop gravity alone would
    // cause: in free fall that is the whole answer, which block Jacobi would take tens of iterations to
    // build; where gravity is balanced the multiple is near zero and CG runs as without it.
    const Eigen::VectorXd* cg_guess = iteration == 0 ? &gravity_drop_ : nullptr;
    bool solved = solve(settings, cg_tolerance, cg_guess);
    if (!solved && exact_first) {
      ++report_.projected_hessians;
      incremental_potential(model, gravity, x, h, nullptr, /*assemble=*/true, /*project=*/true);
      solved = solve(settings, cg_tolerance, cg_guess);
    }
    if (!solved) break;
    ++report_.newton_iterations;
    dx_.array() *= free_mask_.array();
    if (contact_ != nullptr) {
      for (int i = 0; i < num_vertices_; ++i) {
        if (model.inverse_mass[i] == 0.0) dx_.segment<3>(3 * i) = pin_targets_.col(i) - x.col(i);
      }
    }
    const Eigen::Map<const Positions> step(dx_.data(), 3, num_vertices_);
    // With contact in the solve, no trial goes past the step that keeps every pair apart.
    const double max_alpha = contact_ != nullptr ? contact_->max_step(x, step) : 1.0;

    // Backtracking line search on Phi with the Armijo condition. The full step is nearly always
    // taken, so its trial point is evaluated with the gradient and Hessian the next iteration
    // needs (one pass over the elements per iteration); shorter trials are evaluated for the
    // value only, and the accepted one is then assembled. A step shorter than the tolerance is
    // likely the last, so only the gradient is evaluated after it (the residual test reads it);
    // if the residual says otherwise, the next iteration assembles the Hessian first.
    const double slope = gradient_vector().dot(dx_);
    const bool last_step = dx_.lpNorm<Eigen::Infinity>() < settings.newton_tolerance * h;
    // Nor is the Hessian needed after the cap's last iteration: no solve follows it (two of a
    // capped step's three assemblies are used at max_newton_iterations = 2).
    const bool final_iteration = iteration + 1 == settings.max_newton_iterations;
    assembled = !last_step && !final_iteration;
    const auto evaluate_accepted = [&](const Positions& point) {
      return assembled ? evaluate_for_newton(point)
                       : incremental_potential(model, gravity, point, h, &gradient_, /*assemble=*/false,
                                               /*project=*/false);
    };
    const double value_before = value;
    double alpha = max_alpha;
    trial_.noalias() = x + alpha * step;
    double trial_value = evaluate_accepted(trial_);
    bool evaluated_at_trial = true;
    // Near the solution the decrease of Phi falls below its round-off (a light vertex's share of
    // Phi is ~1e-20 of the total), and Armijo can no longer tell: the full step is then taken
    // when it lowers the gradient, the quantity convergence is judged by.
    const double round_off = 1e-13 * std::abs(value);
    const bool decrease_unresolved = std::isfinite(trial_value) &&
                                     std::abs(trial_value - value) <= round_off &&
                                     gradient_vector().norm() < report_.gradient_norms.back();
    while (!decrease_unresolved && !(trial_value <= value + 1e-4 * alpha * slope)) {  // also from NaN
      alpha *= 0.5;
      if (alpha <= 1e-8) break;
      trial_.noalias() = x + alpha * step;
      trial_value =
          incremental_potential(model, gravity, trial_, h, nullptr, /*assemble=*/false, /*project=*/false);
      evaluated_at_trial = false;
    }
    if (alpha <= 1e-8) break;  // no decrease along dx: cannot improve further
    // Expansion: Phi(a) ~ value + slope a + c a^2 through Phi(1) has its minimum at -slope/(2c)
    // (none when c <= 0). In the tail of a step where the cloth buckles, Newton otherwise creeps
    // along the buckling mode by the same small full step iteration after iteration.
    // With contact in the solve the stretch stops where the contact bounds it along dx; the
    // pairs then found cover the segment to the stretched point, which holds the trial point.
    bool stretched = false;
    if (alpha == 1.0 && !last_step && settings.max_step_expansion > 1.0) {
      const double c = trial_value - value - slope;
      const double minimum = c > 0.0 ? -slope / (2.0 * c) : settings.max_step_expansion;
      double stretch = std::min(minimum, settings.max_step_expansion);
      if (minimum > 1.5 && contact_ != nullptr && !pins_moving()) {
        trial_step_ = stretch * dx_;
        const Eigen::Map<const Positions> stretched_step(trial_step_.data(), 3, num_vertices_);
        stretch *= contact_->max_step(x, stretched_step);
      }
      if (minimum > 1.5 && stretch > 1.0 && (contact_ == nullptr || !pins_moving())) {
        x.noalias() += stretch * step;  // x is free: the fallback is trial_
        const double stretched_value =
            incremental_potential(model, gravity, x, h, nullptr, /*assemble=*/false, /*project=*/false);
        if (stretched_value < trial_value) {
          value = stretched_value;
          alpha = stretch;
          evaluate_accepted(x);
          stretched = true;
          ++report_.stretched_steps;
        }
      }
    }
    if (!stretched) {
      x = trial_;
      value = trial_value;
      if (!evaluated_at_trial) evaluate_accepted(x);
    }
    report_.residual = newton_residual(gradient_, model.inverse_mass, h);
    report_.converged = report_.residual < settings.newton_tolerance && pins_on_target();
    int restricted = 0;
    // (With contact, only once every pin is on its target: the tail moves free vertices alone.)
    if (use_tail && !report_.converged && pins_on_target()) {
      // The residual left on a few vertices: iterations on their region, then the whole cloth's
      // gradient again, so that the residual judged is the cloth's.
      restricted =
          tail_.iterate(model, gravity, h, x_start_, x_hat_, penalty_, contact_, tail_settings, hessian_,
                        stencils_, x, gradient_, contact_ != nullptr ? &contact_gradient_ : nullptr);
      use_tail = use_tail && !tail_.collapsed();  // the rest of the step iterates on the whole cloth
      if (restricted > 0) {
        report_.newton_iterations += restricted;
        report_.restricted_iterations += restricted;
        value =
            incremental_potential(model, gravity, x, h, &gradient_, /*assemble=*/false, /*project=*/false);
        assembled = false;
        report_.residual = newton_residual(gradient_, model.inverse_mass, h);
        report_.converged = report_.residual < settings.newton_tolerance && pins_on_target();
        tail_runs_behind = report_.residual < best_residual ? 0 : tail_runs_behind + 1;
        if (tail_runs_behind >= tail_runs_without_progress) use_tail = false;
      }
    }
    record_iteration(alpha, report_.linear_iterations - linear_before, restricted);
    const bool stalled = value_before - value < stalled_fraction * (start_value - value);
    if (report_.residual < best_residual) {
      best_residual = report_.residual;
      best_x_ = x;
      best_value = value;
    }
    diverging = report_.residual > diverging_factor * best_residual && stalled ? diverging + 1 : 0;
    if (diverging >= diverging_iterations) break;
  }
  // A step that stopped diverging, or reached the cap diverging (its residual a hundredfold over
  // the best iterate's while Phi fell by under stalled_fraction of the step's decrease since it:
  // a wing collapsing in the last iterations), ends on the best iterate, with its gradient.
  const bool capped_diverging = !report_.converged && report_.residual > diverging_factor * best_residual &&
                                best_value - value < stalled_fraction * (start_value - value);
  if (diverging >= diverging_iterations || capped_diverging) {
    report_.diverged_stops = 1;
    x = best_x_;
    report_.residual = best_residual;
    if (contact_ != nullptr) contact_->max_step(x, zero_motion_);  // the pairs near the best iterate
    incremental_potential(model, gravity, x, h, &gradient_, /*assemble=*/false, /*project=*/false);
  }
  report_.gradient_norms.push_back(gradient_vector().norm());
  state.v = (x - x_start_) / h;
  penalty_ = nullptr;
  contact_ = nullptr;
  return report_;
}

}  // namespace weft
