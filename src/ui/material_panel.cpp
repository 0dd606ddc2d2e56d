#include <imgui.h>

#include <algorithm>
#include <string>

#include "ui/material_edit.hpp"
#include "ui/panels.hpp"

namespace weft {

namespace {

// A positive value on a log slider; returns true when it changed.
bool log_slider(const char* label, double& value, float min_value, float max_value, const char* format) {
  float shown = static_cast<float>(value);
  if (!ImGui::SliderFloat(label, &shown, min_value, max_value, format, ImGuiSliderFlags_Logarithmic)) return false;
  value = shown;
  return true;
}

}  // namespace

void draw_material_panel(SimulationSession& session) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 230.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340.0f, 0.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Material")) {
    ImGui::End();
    return;
  }
  World& world = session.world();
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    ClothModel& model = world.cloths()[c].model;
    ImGui::PushID(static_cast<int>(c));
    const std::string title = model.name.empty() ? "cloth " + std::to_string(c) : model.name;
    if (ImGui::TreeNodeEx(title.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
      // One stiffness and damping per spring kind, written straight into the SpringSet.
      for (int k = 0; k < spring_kind_count; ++k) {
        const SpringKind kind = static_cast<SpringKind>(k);
        if (model.springs.count(kind) == 0) continue;
        ImGui::PushID(k);
        double stiffness = spring_stiffness(model.springs, kind);
        double damping = spring_damping(model.springs, kind);
        ImGui::TextUnformatted(to_string(kind));
        bool changed = log_slider("stiffness (N/m)", stiffness, 0.1f, 1e5f, "%.4g");
        changed |= log_slider("damping (N s/m)", damping, 1e-5f, 10.0f, "%.3g");
        if (changed) set_spring_params(model.springs, kind, stiffness, damping);
        ImGui::PopID();
      }
      ImGui::Separator();
      double density = area_density(model);
      if (log_slider("density (kg/m^2)", density, 0.01f, 10.0f, "%.3g")) set_area_density(model, density);
      log_slider("mass damping (1/s)", model.mass_damping, 1e-4f, 10.0f, "%.3g");
      log_slider("thickness (m)", model.thickness, 1e-4f, 0.1f, "%.4f");
      ImGui::TextDisabled("membrane and hinge bending: not in the cloth model yet");
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (!world.colliders().empty() && ImGui::TreeNodeEx("friction", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      Collider& collider = world.colliders()[k];
      float friction = static_cast<float>(collider.friction);
      const std::string label = collider.name.empty() ? "collider " + std::to_string(k) : collider.name;
      if (ImGui::SliderFloat(label.c_str(), &friction, 0.0f, 2.0f, "%.2f")) collider.friction = friction;
    }
    ImGui::TreePop();
  }
  ImGui::End();
}

}  // namespace weft
