#include "physics/gravity.hpp"

namespace weft {

void add_gravity_forces(const Eigen::VectorXd& mass, const Vec3& gravity, Positions& force) {
  force.noalias() += gravity * mass.transpose();
}

double gravitational_energy(const Eigen::VectorXd& mass, const Vec3& gravity, const Positions& x) {
  // E = -sum_i m_i g . x_i
  return -(gravity.transpose() * x * mass)(0);
}

}  // namespace weft
