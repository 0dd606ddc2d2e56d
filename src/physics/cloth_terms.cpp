#include "physics/cloth_terms.hpp"

#include <array>
#include <cstddef>

#include "core/parallel_chunks.hpp"
#include "physics/gravity.hpp"
#include "physics/mass_damping.hpp"

namespace weft {

TermEnergies& TermEnergies::operator+=(const TermEnergies& other) {
  springs += other.springs;
  membrane += other.membrane;
  bending += other.bending;
  pressure += other.pressure;
  gravity += other.gravity;
  return *this;
}

void prepare_hessian(const ClothModel& model, SparseHessian& hessian, HessianStencils& stencils,
                     bool hinges_in_matrix) {
  hessian.begin_pattern(static_cast<int>(model.rest_positions.cols()));
  stencils = HessianStencils{};
  if (model.springs.size() > 0) stencils.springs = hessian.add_stencil<2>(model.springs.vertices);
  if (model.membrane.enabled() || model.air_drag.enabled() || model.pressure.enabled) {
    stencils.triangles = hessian.add_stencil<3>(model.triangles);
  }
  if (model.bending.enabled() && hinges_in_matrix) {
    stencils.hinges = hessian.add_stencil<4>(model.bending.hinges);
  }
  hessian.finish_pattern();
  std::vector<char> fixed(model.inverse_mass.size());
  for (Eigen::Index i = 0; i < model.inverse_mass.size(); ++i) fixed[i] = model.inverse_mass[i] == 0.0;
  hessian.set_fixed_vertices(fixed);
}

double evaluate_potential(const ClothModel& model, const Vec3& gravity, const Positions& x, Positions* gradient,
                          SparseHessian* hessian, const HessianStencils& stencils, bool project,
                          TermEnergies* energies) {
  TermEnergies terms;
  terms.gravity = gravitational_energy(model.mass, gravity, x);
  if (gradient != nullptr) add_gravity_forces(model.mass, -gravity, *gradient);  // dE/dx = -m g
  if (model.springs.size() > 0) {
    terms.springs = evaluate_springs(model.springs, x, gradient, hessian, stencils.springs, project);
  }
  if (model.membrane.enabled()) {
    terms.membrane = evaluate_membrane(model.membrane, model.triangles, x, gradient, hessian, stencils.triangles, project);
  }
  if (model.bending.enabled()) {
    terms.bending = evaluate_bending(model.bending, x, gradient, stencils.hinges >= 0 ? hessian : nullptr,
                                     stencils.hinges, project);
  }
  if (model.pressure.enabled) {
    terms.pressure = evaluate_pressure(model.pressure, model.triangles, x, gradient, hessian, stencils.triangles, project);
  }
  if (energies != nullptr) *energies = terms;
  return terms.gravity + terms.elastic();
}

double evaluate_dissipation(const ClothModel& model, const Positions& x_start, const Positions& x, double h,
                            Positions* gradient, SparseHessian* hessian, const HessianStencils& stencils) {
  double energy = 0.0;
  if (model.springs.size() > 0) {
    energy += evaluate_spring_damping(model.springs, x_start, x, h, gradient, hessian, stencils.springs);
  }
  if (model.air_drag.enabled()) {
    energy += evaluate_air_drag_dissipation(model.air_drag, model.triangles, x_start, x, h, gradient, hessian,
                                            stencils.triangles);
  }
  if (model.mass_damping > 0.0) {
    // Rayleigh damping c M v as the potential c/(2h) |x - x_start|^2_M.
    energy += evaluate_mass_quadratic(model.mass, model.mass_damping / h, x, x_start, gradient, hessian);
  }
  return energy;
}

double evaluate_mass_quadratic(const Eigen::VectorXd& mass, double weight, const Positions& x,
                               const Positions& center, Positions* gradient, SparseHessian* hessian) {
  constexpr std::size_t chunks = 64;
  std::array<double, chunks> partials;
  const double sum = chunked_sum(static_cast<int>(x.cols()), partials, [&](int begin, int end) {
    double partial = 0.0;
    for (int i = begin; i < end; ++i) {
      const Vec3 offset = x.col(i) - center.col(i);
      partial += mass[i] * offset.squaredNorm();
      if (gradient != nullptr) gradient->col(i) += (weight * mass[i]) * offset;
    }
    return partial;
  });
  if (hessian != nullptr) hessian->add_diagonal(weight, mass);
  return 0.5 * weight * sum;
}

void compute_forces(const ClothModel& model, const Vec3& gravity, const Positions& x, const Positions& v,
                    Positions& force) {
  // The energy terms without their own force routine add their gradient, then the sign flips.
  force.setZero();
  if (model.membrane.enabled()) evaluate_membrane(model.membrane, model.triangles, x, &force, nullptr, -1, false);
  if (model.bending.enabled()) evaluate_bending(model.bending, x, &force, nullptr, -1, false);
  if (model.pressure.enabled) evaluate_pressure(model.pressure, model.triangles, x, &force, nullptr, -1, false);
  force = -force;
  add_gravity_forces(model.mass, gravity, force);
  if (model.springs.size() > 0) add_spring_forces(model.springs, x, v, force);
  if (model.air_drag.enabled()) add_air_drag_forces(model.air_drag, model.triangles, x, v, force);
  if (model.mass_damping > 0.0) add_mass_damping_forces(model.mass, model.mass_damping, v, force);
}

}  // namespace weft
