#include "physics/symplectic_euler.hpp"

#include "physics/cloth_terms.hpp"

namespace weft {

void symplectic_euler_step(const ClothModel& model, ClothState& state, const Vec3& gravity, double h) {
  // Forces at the start of the step; velocity first, then position with the new velocity.
  compute_forces(model, gravity, state.x, state.v, state.force);
  state.v.noalias() += h * (state.force * model.inverse_mass.asDiagonal());
  state.x.noalias() += h * state.v;
}

}  // namespace weft
