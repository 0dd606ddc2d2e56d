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
                                        const ContactPenalty* penalty,
                                        const IncrementalPotentialParts* at_end) {
  const ClothModel& model = cloth.model;
  const Positions& x1 = cloth.state.x;
  const Positions& v1 = cloth.state.v;
  const bool penalized = penalty != nullptr && penalty->active();
  dx_ = x1 - x0_;
  dv_ = v1 - v0_;
  dissipation_gradient_.setZero(3, x1.cols());
  evaluate_dissipation(model, x0_, x1, h, &dissipation_gradient_, nullptr, HessianStencils{});
  // U includes the penalty: the solve saw it as potential energy. The row r is the incremental
  // potential's gradient at x1 (M (x1 - x_hat) / h^2 = M dv / h), the solve's own last one when
  // it was taken there.
  double penalty_end = 0.0;
  if (at_end != nullptr) {
    potential_end_ = at_end->potential;
    penalty_end = at_end->penalty;
  } else {
    row_.setZero(3, x1.cols());
    potential_end_ = evaluate_potential(model, gravity, x1, &row_, nullptr, HessianStencils{}, false);
    if (penalized) penalty_end = penalty->evaluate(x1, &row_, nullptr);
    row_ += dissipation_gradient_;
    for (Eigen::Index i = 0; i < row_.cols(); ++i) row_.col(i) += (model.mass[i] / h) * dv_.col(i);
  }
  const Positions& row = at_end != nullptr ? at_end->gradient : row_;
  const double penalty_start = penalized ? penalty->evaluate(x0_, nullptr, nullptr) : 0.0;

  EnergyFlows flows;
  // Vertex i's row r_i: for a pinned vertex minus the pin's reaction, whose work is external; for a
  // free one what the solve left unbalanced, whose work the step added (the residual flow takes it
  // out). dx . grad U(x1), for the Bregman divergence, is dx . (r - M dv / h - grad D).
  // Contact inside the solve (at_end->contact_gradient, when not empty) is a force like the
  // damping's: its work over the step, dx . grad C(x1), is the contact flow.
  const bool solve_contact = at_end != nullptr && at_end->contact_gradient.cols() == dx_.cols();
  double contact_work = 0.0;
  double potential_work = 0.0;
  for (Eigen::Index i = 0; i < dx_.cols(); ++i) {
    const double work = dx_.col(i).dot(row.col(i));
    if (solve_contact) {
      const double pushed = dx_.col(i).dot(at_end->contact_gradient.col(i));
      contact_work += pushed;
      potential_work -= pushed;
    }
    potential_work += work - dx_.col(i).dot((model.mass[i] / h) * dv_.col(i) + dissipation_gradient_.col(i));
    if (model.inverse_mass[i] == 0.0) {
      flows.external_work += work;
    } else {
      flows.residual -= work;
    }
  }
  const double bregman = (potential_start_ + penalty_start) - (potential_end_ + penalty_end) + potential_work;
  flows.integrator = 0.5 * mass_norm_squared(model.mass, dv_) + bregman;
  // grad D(x1) = -F_d(v1): the damping force's power over the step is -dx . grad D.
  flows.damping = (dissipation_gradient_.cwiseProduct(dx_)).sum();
  flows.contact = penalty_end - penalty_start + contact_work;
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
