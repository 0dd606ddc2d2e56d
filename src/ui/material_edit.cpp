#include "ui/material_edit.hpp"

#include "core/triangle_mesh.hpp"

namespace weft {

double spring_stiffness(const SpringSet& springs, SpringKind kind) {
  return springs.count(kind) > 0 ? springs.stiffness[springs.kind_begin[static_cast<int>(kind)]] : 0.0;
}

double spring_damping(const SpringSet& springs, SpringKind kind) {
  return springs.count(kind) > 0 ? springs.damping[springs.kind_begin[static_cast<int>(kind)]] : 0.0;
}

double area_density(const ClothModel& model) {
  const double area = surface_area(model.rest_positions, model.triangles);
  return area > 0.0 ? model.mass.sum() / area : 0.0;
}

void set_area_density(ClothModel& model, double density) {
  const double current = area_density(model);
  if (current <= 0.0 || density <= 0.0) return;
  const double factor = density / current;
  model.mass *= factor;
  for (Eigen::Index i = 0; i < model.inverse_mass.size(); ++i) {
    if (model.inverse_mass[i] > 0.0) model.inverse_mass[i] = 1.0 / model.mass[i];
  }
}

}  // namespace weft
