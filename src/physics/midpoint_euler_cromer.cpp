#include "physics/midpoint_euler_cromer.hpp"

#include "physics/cloth_terms.hpp"

namespace weft {

void midpoint_euler_cromer_step(Cloth& cloth, const Vec3& gravity, double h, ExplicitWorkspace& workspace) {
  ClothState& state = cloth.state;
  const auto inverse_mass = cloth.model.inverse_mass.asDiagonal();
  workspace.resize(cloth.num_vertices());
  // Half a kick with the start-of-step force: the velocity at the half step.
  compute_forces(cloth.model, gravity, state.x, state.v, workspace.force);
  workspace.v_mid.noalias() = state.v + 0.5 * h * (workspace.force * inverse_mass);
  // The drift with that velocity, then the second half kick with the force at the new positions.
  state.x.noalias() += h * workspace.v_mid;
  compute_forces(cloth.model, gravity, state.x, workspace.v_mid, workspace.force);
  state.v.noalias() = workspace.v_mid + 0.5 * h * (workspace.force * inverse_mass);
}

}  // namespace weft
