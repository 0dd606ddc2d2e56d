#include "sim/energy_ledger.hpp"

#include "physics/cloth_terms.hpp"

namespace weft {

namespace {

// Sum over vertices of m_i |a_i|^2 (a loop: no temporaries, steps allocate nothing).
double mass_norm_squared(const Eigen::VectorXd& mass, const Positions& a) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < a.cols(); ++i) sum += mass[i] * a.col(i).squaredNorm();
  return sum;
}

}  // namespace

EnergyFlows& EnergyFlows::operator+=(const EnergyFlows& other) {
  external_work += other.external_work;
  damping += other.damping;
  integrator += other.integrator;
  contact += other.contact;
  plastic += other.plastic;
  residual += other.residual;
  return *this;
}

double kinetic_energy(const Cloth& cloth) { return 0.5 * mass_norm_squared(cloth.model.mass, cloth.state.v); }

double potential_energy(const Cloth& cloth, const Vec3& gravity) {
  return evaluate_potential(cloth.model, gravity, cloth.state.x, nullptr, nullptr, HessianStencils{}, false);
}

void SolveLedger::begin(const Cloth& cloth, const Vec3& gravity, bool need_gradient) {
  x0_ = cloth.state.x;
  v0_ = cloth.state.v;
  const bool carried = carried_ && !need_gradient && gravity == carried_gravity_;
  carried_ = false;
  if (carried) {
    potential_start_ = carried_potential_;
    return;
  }
  Positions* gradient = nullptr;
  if (need_gradient) {
    gradient_.setZero(3, cloth.state.x.cols());
    gradient = &gradient_;
  }
  potential_start_ =
      evaluate_potential(cloth.model, gravity, cloth.state.x, gradient, nullptr, HessianStencils{}, false);
}

void SolveLedger::carry_potential(double potential, const Vec3& gravity) {
  carried_ = true;
  carried_potential_ = potential;
  carried_gravity_ = gravity;
}

EnergyFlows SolveLedger::implicit_euler(const Cloth& cloth, const Vec3& gravity, double h,
                                        const ContactPenalty* penalty) {
  const ClothModel& model = cloth.model;
  const Positions& x1 = cloth.state.x;
  const Positions& v1 = cloth.state.v;
  // U includes the penalty: the solve saw it as potential energy.
  gradient_.setZero(3, x1.cols());
  potential_end_ = evaluate_potential(model, gravity, x1, &gradient_, nullptr, HessianStencils{}, false);
  double penalty_start = 0.0, penalty_end = 0.0;
  if (penalty != nullptr && penalty->active()) {
    penalty_start = penalty->evaluate(x0_, nullptr, nullptr);
    penalty_end = penalty->evaluate(x1, &gradient_, nullptr);
  }
  dissipation_gradient_.setZero(3, x1.cols());
  evaluate_dissipation(model, x0_, x1, h, &dissipation_gradient_, nullptr, HessianStencils{});

  dx_ = x1 - x0_;
  dv_ = v1 - v0_;
  const double bregman = (potential_start_ + penalty_start) - (potential_end_ + penalty_end) +
                         (gradient_.cwiseProduct(dx_)).sum();
  EnergyFlows flows;
  flows.integrator = 0.5 * mass_norm_squared(model.mass, dv_) + bregman;
  // grad D(x1) = -F_d(v1): the damping force's power over the step is -dx . grad D.
  flows.damping = (dissipation_gradient_.cwiseProduct(dx_)).sum();
  // Vertex i's row of the incremental potential's gradient, r_i = M dv / h + grad U + grad D: for a
  // pinned vertex minus the pin's reaction, whose work is external; for a free one what the solve
  // left unbalanced, whose work the step added (the residual flow takes it out).
  for (Eigen::Index i = 0; i < dx_.cols(); ++i) {
    const Vec3 row = (model.mass[i] / h) * dv_.col(i) + gradient_.col(i) + dissipation_gradient_.col(i);
    const double work = dx_.col(i).dot(row);
    if (model.inverse_mass[i] == 0.0) {
      flows.external_work += work;
    } else {
      flows.residual -= work;
    }
  }
  flows.contact = penalty_end - penalty_start;
  return flows;
}

EnergyFlows SolveLedger::symplectic_euler(const Cloth& cloth, const Vec3& gravity) {
  const ClothModel& model = cloth.model;
  const Positions& x1 = cloth.state.x;
  potential_end_ = potential_energy(cloth, gravity);
  dx_ = x1 - x0_;
  dv_ = cloth.state.v - v0_;
  // F = F_U + F_d with F_U = -grad U(x0): the damping part is what the total leaves.
  const Positions& force = cloth.state.force;
  const double bregman = potential_end_ - potential_start_ - (gradient_.cwiseProduct(dx_)).sum();
  EnergyFlows flows;
  flows.integrator = 0.5 * mass_norm_squared(model.mass, dv_) - bregman;
  flows.damping = -((force + gradient_).cwiseProduct(dx_)).sum();
  // A pinned vertex does not accelerate: the pin holds it against the force, -F, over dx.
  for (Eigen::Index i = 0; i < dx_.cols(); ++i) {
    if (model.inverse_mass[i] == 0.0) flows.external_work -= dx_.col(i).dot(force.col(i));
  }
  return flows;
}

EnergyFlows SolveLedger::whole_change(const Cloth& cloth, const Vec3& gravity) {
  potential_end_ = potential_energy(cloth, gravity);
  EnergyFlows flows;
  flows.integrator = (0.5 * mass_norm_squared(cloth.model.mass, v0_) + potential_start_) -
                     (kinetic_energy(cloth) + potential_end_);
  return flows;
}

}  // namespace weft
