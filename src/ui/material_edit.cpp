#include "ui/material_edit.hpp"

#include <algorithm>

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

ClothMaterial read_material(const ClothModel& model) {
  ClothMaterial material;
  for (int k = 0; k < spring_kind_count; ++k) {
    material.springs.stiffness[k] = spring_stiffness(model.springs, static_cast<SpringKind>(k));
    material.springs.damping[k] = spring_damping(model.springs, static_cast<SpringKind>(k));
  }
  material.membrane = model.membrane.material;
  material.bending_stiffness = model.bending.stiffness;
  material.normal_drag = model.air_drag.normal_coefficient;
  material.tangential_drag = model.air_drag.tangential_coefficient;
  material.wind = model.air_drag.wind;
  material.area_density = area_density(model);
  material.mass_damping = model.mass_damping;
  material.thickness = model.thickness;
  return material;
}

void apply_material(ClothModel& model, const ClothMaterial& material) {
  for (int k = 0; k < spring_kind_count; ++k) {
    const SpringKind kind = static_cast<SpringKind>(k);
    if (model.springs.count(kind) > 0) {
      set_spring_params(model.springs, kind, material.springs.stiffness[k], material.springs.damping[k]);
    }
  }
  if (model.membrane.enabled()) model.membrane.material = material.membrane;
  if (model.bending.enabled()) model.bending.stiffness = material.bending_stiffness;
  // Drag is tuned, never switched on or off: the implicit solver's Hessian pattern depends on it.
  AirDragTerm drag = model.air_drag;
  drag.normal_coefficient = std::max(material.normal_drag, 0.0);
  drag.tangential_coefficient = std::max(material.tangential_drag, 0.0);
  drag.wind = material.wind;
  if (model.air_drag.enabled() && drag.enabled()) model.air_drag = drag;
  if (material.area_density != area_density(model)) set_area_density(model, material.area_density);
  model.mass_damping = material.mass_damping;
  model.thickness = material.thickness;
}

}  // namespace weft
