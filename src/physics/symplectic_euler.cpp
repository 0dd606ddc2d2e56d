#include "physics/symplectic_euler.hpp"

#include "physics/gravity.hpp"
#include "physics/mass_damping.hpp"

namespace weft {

void symplectic_euler_step(Cloth& cloth, const Vec3& gravity, double h) {
  ClothState& state = cloth.state;
  const ClothModel& model = cloth.model;
  // Forces at the start of the step.
  state.force.setZero();
  add_gravity_forces(model.mass, gravity, state.force);
  add_spring_forces(model.springs, state.x, state.v, state.force);
  if (model.mass_damping > 0.0) add_mass_damping_forces(model.mass, model.mass_damping, state.v, state.force);
  // Velocity first, then position with the new velocity.
  state.v.noalias() += h * (state.force * model.inverse_mass.asDiagonal());
  state.x.noalias() += h * state.v;
}

}  // namespace weft
