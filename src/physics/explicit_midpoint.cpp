#include "physics/explicit_midpoint.hpp"

#include "physics/cloth_terms.hpp"

namespace weft {

void ExplicitWorkspace::resize(int num_vertices) {
  if (x_start.cols() == num_vertices) return;
  for (Positions* m : {&x_start, &v_start, &x_mid, &v_mid, &force}) m->setZero(3, num_vertices);
}

void explicit_midpoint_step(Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace) {
  ClothState& state = cloth.state;
  const auto inverse_mass = cloth.model.inverse_mass.asDiagonal();
  workspace.resize(cloth.num_vertices());
  // Half step to the midpoint with the start-of-step force.
  compute_forces(cloth.model, gravity, state.x, state.v, workspace.force);
  workspace.x_mid.noalias() = state.x + 0.5 * h * state.v;
  workspace.v_mid.noalias() = state.v + 0.5 * h * (workspace.force * inverse_mass);
  // Full step with the midpoint's velocity and force.
  compute_forces(cloth.model, gravity, workspace.x_mid, workspace.v_mid, workspace.force);
  state.x.noalias() += h * workspace.v_mid;
  state.v.noalias() += h * (workspace.force * inverse_mass);
}

}  // namespace weft
