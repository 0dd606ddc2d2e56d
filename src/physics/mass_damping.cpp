#include "physics/mass_damping.hpp"

namespace weft {

void add_mass_damping_forces(const Eigen::VectorXd& mass, double coefficient, const Positions& v, Positions& force) {
  force.noalias() -= coefficient * (v * mass.asDiagonal());
}

}  // namespace weft
