#include "ui/session_settings.hpp"

#include <utility>

namespace weft {

namespace {

bool same_springs(const SpringStiffness& a, const SpringStiffness& b) {
  for (int k = 0; k < spring_kind_count; ++k) {
    if (a.stiffness[k] != b.stiffness[k] || a.damping[k] != b.damping[k]) return false;
  }
  return true;
}

bool same_membrane(const MembraneMaterial& a, const MembraneMaterial& b) {
  return a.young_modulus == b.young_modulus && a.poisson_ratio == b.poisson_ratio &&
         a.thickness == b.thickness && a.compression_factor == b.compression_factor &&
         a.min_stretch == b.min_stretch;
}

}  // namespace

bool operator==(const ClothMaterial& a, const ClothMaterial& b) {
  return same_springs(a.springs, b.springs) && same_membrane(a.membrane, b.membrane) &&
         a.bending_stiffness == b.bending_stiffness && a.normal_drag == b.normal_drag &&
         a.tangential_drag == b.tangential_drag && a.wind == b.wind && a.area_density == b.area_density &&
         a.mass_damping == b.mass_damping && a.thickness == b.thickness;
}

SessionSettings read_settings(const SimulationSession& session, const VertexDrag& drag) {
  SessionSettings settings;
  const World& world = session.world();
  settings.generation = session.generation();
  settings.solver = world.settings;
  settings.max_time_step = session.max_time_step();
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    settings.materials.push_back(read_material(world.cloths()[c].model));
    settings.masses.push_back(world.cloths()[c].model.mass);
    settings.contact.push_back(world.contact_material(static_cast<int>(c)));
  }
  for (const Collider& collider : world.colliders())
    settings.collider_friction.emplace_back(collider.static_friction, collider.friction);
  settings.pause_on_contact = session.pause_on_contact;
  settings.drag = drag;
  return settings;
}

bool apply_settings(SimulationSession& session, const SessionSettings& settings) {
  World& world = session.world();
  if (settings.generation != session.generation() || settings.materials.size() != world.cloths().size() ||
      settings.masses.size() != world.cloths().size() ||
      settings.collider_friction.size() != world.colliders().size())
    return false;
  const int threads = world.settings.threads;
  world.settings = settings.solver;
  world.settings.threads = threads;
  if (settings.max_time_step != session.max_time_step()) session.set_max_time_step(settings.max_time_step);
  for (size_t c = 0; c < settings.materials.size(); ++c) {
    // Compared through the const view: the mutable one tells the energy ledger the cloth changed.
    const ClothModel& model = std::as_const(world).cloths()[c].model;
    // The masses are copied, not rescaled from a density (which would round differently).
    ClothMaterial material = settings.materials[c];
    material.area_density = area_density(model);
    if (read_material(model) != material) apply_material(world.cloths()[c].model, material);
    if (model.mass.size() == settings.masses[c].size() && model.mass != settings.masses[c]) {
      ClothModel& edited = world.cloths()[c].model;
      edited.mass = settings.masses[c];
      // As set_area_density: pinned vertices (inverse mass 0) stay pinned.
      for (Eigen::Index i = 0; i < edited.inverse_mass.size(); ++i) {
        if (edited.inverse_mass[i] > 0.0) edited.inverse_mass[i] = 1.0 / edited.mass[i];
      }
    }
    world.contact_material(static_cast<int>(c)) = settings.contact[c];
  }
  for (size_t k = 0; k < settings.collider_friction.size(); ++k) {
    world.colliders()[k].static_friction = settings.collider_friction[k].first;
    world.colliders()[k].friction = settings.collider_friction[k].second;
  }
  session.pause_on_contact = settings.pause_on_contact;
  return true;
}

}  // namespace weft
