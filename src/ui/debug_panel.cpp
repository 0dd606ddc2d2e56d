#include <imgui.h>

#include "ui/panels.hpp"

namespace weft {

void draw_debug_panel(SimulationSession& session, ViewerState& state) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 270.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(400.0f, 0.0f), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Display and collisions")) {
    ImGui::End();
    return;
  }
  ViewOptions& view = state.view;
  ImGui::PushItemWidth(180.0f);  // leaves the labels their whole width
  ImGui::TextUnformatted("Cloth");
  ImGui::SliderInt("subdivision", &view.subdivision_levels, 0, 2);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Loop subdivision levels of the displayed mesh");
  ImGui::Checkbox("wireframe", &view.wireframe);
  ImGui::SameLine();
  ImGui::Checkbox("strain", &view.strain);
  ImGui::SameLine();
  ImGui::Checkbox("pins", &view.pins);
  if (view.strain) ImGui::SliderFloat("strain range", &view.strain_range, 0.001f, 0.5f, "%.3f", ImGuiSliderFlags_Logarithmic);
  ImGui::Checkbox("colliders", &view.colliders);
  ImGui::SameLine();
  ImGui::Checkbox("cutaway", &view.cutaway);
  ImGui::SameLine();
  ImGui::Checkbox("ground grid", &view.ground_grid);

  ImGui::Separator();
  ImGui::TextUnformatted("Collisions");
  ImGui::Checkbox("bounding boxes", &view.boxes);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(120.0f);
  ImGui::SliderInt("depth", &view.box_depth, 0, 12);
  ImGui::Checkbox("tangles", &view.tangles);
  ImGui::SameLine();
  ImGui::Checkbox("contacts", &view.contacts);
  if (view.contacts) {
    float scale = static_cast<float>(view.impulse_scale);
    if (ImGui::SliderFloat("arrow scale (m/N s)", &scale, 0.1f, 1e4f, "%.1f", ImGuiSliderFlags_Logarithmic)) {
      view.impulse_scale = scale;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Impulse arrows' length per unit impulse");
    float longest = static_cast<float>(view.max_arrow_length);
    if (ImGui::SliderFloat("arrow cap (scene size)", &longest, 0.005f, 1.0f, "%.3f",
                           ImGuiSliderFlags_Logarithmic)) {
      view.max_arrow_length = longest;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("All arrows shrink together when the largest impulse's would be longer");
  }
  ImGui::Checkbox("pause on first contact", &session.pause_on_contact);
  for (size_t c = 0; c < session.world().cloths().size(); ++c) {
    ImGui::PushID(static_cast<int>(c));
    ImGui::Checkbox("self-collision", &session.world().contact_material(static_cast<int>(c)).self_collision);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(120.0f);
    float thickness = static_cast<float>(session.world().cloths()[c].model.thickness);
    if (ImGui::SliderFloat("thickness (m)", &thickness, 1e-4f, 0.1f, "%.4f", ImGuiSliderFlags_Logarithmic)) {
      session.world().cloths()[c].model.thickness = thickness;
    }
    ImGui::PopID();
  }
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
  ImGui::TextWrapped("contacts: vertex-face red (cloth-solid) / yellow (cloth-cloth) / orange (soft body), edge-edge green / cyan / violet");
  ImGui::PopStyleColor();

  ImGui::Separator();
  if (ImGui::Button("Reload shaders")) state.reload_shaders = true;
  ImGui::SameLine();
  if (ImGui::Button("Screenshot")) state.save_screenshot = true;
  ImGui::SameLine();
  ImGui::Checkbox("record", &state.record_frames);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Save every drawn frame as a PNG");
  if (!state.last_saved.empty()) ImGui::TextDisabled("saved %s", state.last_saved.c_str());
  ImGui::PopItemWidth();
  if (!state.shader_message.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", state.shader_message.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::End();
}

}  // namespace weft
