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
  ImGui::SetNextWindowSize(ImVec2(480.0f, 0.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Material")) {
    ImGui::End();
    return;
  }
  ImGui::PushItemWidth(220.0f);  // room for the labels with their units
  World& world = session.world();
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    ClothModel& model = world.cloths()[c].model;
    ImGui::PushID(static_cast<int>(c));
    const std::string title = model.name.empty() ? "cloth " + std::to_string(c) : model.name;
    if (ImGui::TreeNodeEx(title.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) {
      // Edit a copy of the material and write it back when a control changed it.
      ClothMaterial material = read_material(model);
      bool changed = false;
      // One stiffness and damping per spring kind.
      for (int k = 0; k < spring_kind_count; ++k) {
        const SpringKind kind = static_cast<SpringKind>(k);
        if (model.springs.count(kind) == 0) continue;
        ImGui::PushID(k);
        ImGui::TextUnformatted(to_string(kind));
        changed |= log_slider("stiffness (N/m)", material.springs.stiffness[k], 0.1f, 1e5f, "%.4g");
        changed |= log_slider("damping (N s/m)", material.springs.damping[k], 1e-5f, 10.0f, "%.3g");
        ImGui::PopID();
      }
      if (model.membrane.enabled()) {
        ImGui::TextUnformatted("membrane (StVK)");
        MembraneMaterial& membrane = material.membrane;
        changed |= log_slider("Young's modulus (Pa)", membrane.young_modulus, 1e2f, 1e9f, "%.3g");
        float poisson = static_cast<float>(membrane.poisson_ratio);
        if (ImGui::SliderFloat("Poisson ratio", &poisson, 0.0f, 0.49f, "%.3f")) {
          membrane.poisson_ratio = poisson;
          changed = true;
        }
        float compression = static_cast<float>(membrane.compression_factor);
        if (ImGui::SliderFloat("compression factor", &compression, 0.01f, 1.0f, "%.2f")) {
          membrane.compression_factor = compression;
          changed = true;
        }
        float smallest = static_cast<float>(membrane.min_stretch);
        if (ImGui::SliderFloat("smallest stretch (0: off)", &smallest, 0.0f, 0.99f, "%.2f")) {
          membrane.min_stretch = smallest;
          changed = true;
        }
        changed |= log_slider("membrane thickness (m)", membrane.thickness, 1e-5f, 1e-2f, "%.2e");
      }
      if (model.bending.enabled()) {
        changed |= log_slider("bending stiffness (J)", material.bending_stiffness, 1e-8f, 1.0f, "%.3g");
        ImGui::TextDisabled("bending model: %s (docs/scenes.md)", to_string(model.bending.model));
      }
      if (model.air_drag.enabled()) {
        changed |= log_slider("normal drag (kg/m^2 s)", material.normal_drag, 1e-4f, 10.0f, "%.3g");
        changed |= log_slider("tangential drag (kg/m^2 s)", material.tangential_drag, 1e-4f, 10.0f, "%.3g");
        float wind[3] = {static_cast<float>(material.wind.x()), static_cast<float>(material.wind.y()),
                         static_cast<float>(material.wind.z())};
        if (ImGui::DragFloat3("wind (m/s)", wind, 0.05f, -50.0f, 50.0f, "%.2f")) {
          material.wind = Vec3(wind[0], wind[1], wind[2]);
          changed = true;
        }
      }
      ImGui::Separator();
      changed |= log_slider("density (kg/m^2)", material.area_density, 0.01f, 10.0f, "%.3g");
      changed |= log_slider("mass damping (1/s)", material.mass_damping, 1e-4f, 10.0f, "%.3g");
      changed |= log_slider("thickness (m)", material.thickness, 1e-4f, 0.1f, "%.4f");
      if (changed) apply_material(model, material);
      if (!model.membrane.enabled() || !model.bending.enabled() || !model.air_drag.enabled()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped(
            "terms off in the scene file stay off: %s%s%s", model.membrane.enabled() ? "" : "membrane ",
            model.bending.enabled() ? "" : "bending ", model.air_drag.enabled() ? "" : "air drag");
        ImGui::PopStyleColor();
      }
      ImGui::TreePop();
    }
    ImGui::PopID();
  }
  if (ImGui::TreeNodeEx("friction (static / kinetic)", ImGuiTreeNodeFlags_DefaultOpen)) {
    const auto pair_slider = [](const std::string& label, double& static_friction, double& kinetic_friction) {
      float values[2] = {static_cast<float>(static_friction), static_cast<float>(kinetic_friction)};
      if (ImGui::SliderFloat2(label.c_str(), values, 0.0f, 2.0f, "%.2f")) {
        static_friction = values[0];
        kinetic_friction = values[1];
      }
    };
    for (size_t c = 0; c < world.cloths().size(); ++c) {
      ContactMaterial& material = world.contact_material(static_cast<int>(c));
      pair_slider("cloth " + world.cloths()[c].model.name, material.static_friction, material.kinetic_friction);
    }
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      Collider& collider = world.colliders()[k];
      const std::string name = collider.name.empty() ? std::to_string(k) : collider.name;
      pair_slider("collider " + name, collider.static_friction, collider.friction);
    }
    ImGui::TreePop();
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace weft
