#include "physics/gravity.hpp"

namespace weft {

void add_gravity_forces(const Eigen::VectorXd& mass, const Vec3& gravity, Positions& force) {
  force.noalias() += gravity * mass.transpose();
}

double gravitational_energy(const Eigen::VectorXd& mass, const Vec3& gravity, const Positions& x) {
  // E = -sum_i m_i g . x_i (a loop: the product g^T x would make a temporary row)
  double energy = 0.0;
  for (Eigen::Index i = 0; i < x.cols(); ++i) energy -= mass[i] * gravity.dot(x.col(i));
  return energy;
}

}  // namespace weft
