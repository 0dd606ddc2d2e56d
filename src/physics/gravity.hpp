#pragma once
// Uniform gravity: force m g on each vertex, energy -sum m g . x.
#include "core/math.hpp"

namespace weft {

void add_gravity_forces(const Eigen::VectorXd& mass, const Vec3& gravity, Positions& force);
double gravitational_energy(const Eigen::VectorXd& mass, const Vec3& gravity, const Positions& x);

}  // namespace weft
