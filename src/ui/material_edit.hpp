#pragma once
// Live material edits on a built cloth, between steps, without rebuilding the world. Every
// integrator reads the edited values afresh each step: the implicit solver caches only the
// Hessian's sparsity pattern and which vertices are pinned, neither of which these change. A
// term the scene left off has no rest data (no hinges, no rest triangles) and stays off.
#include "physics/cloth.hpp"

namespace weft {

// Stiffness (N/m) and damping (N s/m) of the springs of one kind (they share one value); 0 if none.
double spring_stiffness(const SpringSet& springs, SpringKind kind);
double spring_damping(const SpringSet& springs, SpringKind kind);

// Area density (kg/m^2): total vertex mass over the rest area.
double area_density(const ClothModel& model);
// Scales every vertex mass (and inverse mass, pins keep 0) to the new area density.
void set_area_density(ClothModel& model, double density);

// The editable material of one cloth, as the material panel shows it.
struct ClothMaterial {
  SpringStiffness springs;          // per kind; only kinds the cloth has are applied
  MembraneMaterial membrane;        // applied only if the cloth has the membrane term
  double bending_stiffness = 0.0;   // J; applied only if the cloth has hinges
  double normal_drag = 0.0;         // kg/(m^2 s)
  double tangential_drag = 0.0;     // kg/(m^2 s)
  Vec3 wind = Vec3::Zero();         // m/s
  double area_density = 0.0;        // kg/m^2
  double mass_damping = 0.0;        // 1/s
  double thickness = 0.005;         // m, collision thickness
};

ClothMaterial read_material(const ClothModel& model);
// Writes every value of `material` the cloth's enabled terms use into the model. Air drag is
// tuned only while on and only to values that keep it on.
void apply_material(ClothModel& model, const ClothMaterial& material);

}  // namespace weft
