#pragma once
// Mass-proportional (Rayleigh) damping: f_i = -c m_i v_i, a stand-in for still air that damps
// rigid motion too (the springs' damping only damps stretching). c in 1/s; the air-drag term
// (air_drag.hpp) models the air itself.
#include "core/math.hpp"

namespace weft {

void add_mass_damping_forces(const Eigen::VectorXd& mass, double coefficient, const Positions& v, Positions& force);

}  // namespace weft
