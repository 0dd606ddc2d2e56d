#pragma once
// Live material edits on a built cloth, between steps, without rebuilding the world. Every
// integrator reads the edited arrays afresh each step: the implicit solver caches only the
// Hessian's sparsity pattern and which vertices are pinned, neither of which these change.
#include "physics/cloth.hpp"

namespace weft {

// Stiffness (N/m) and damping (N s/m) of the springs of one kind (they share one value); 0 if none.
double spring_stiffness(const SpringSet& springs, SpringKind kind);
double spring_damping(const SpringSet& springs, SpringKind kind);

// Area density (kg/m^2): total vertex mass over the rest area.
double area_density(const ClothModel& model);
// Scales every vertex mass (and inverse mass, pins keep 0) to the new area density.
void set_area_density(ClothModel& model, double density);

}  // namespace weft
