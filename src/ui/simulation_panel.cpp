#include <imgui.h>

#include <algorithm>
#include <filesystem>

#include "ui/panels.hpp"

namespace weft {

void draw_simulation_panel(const SimulationSession& session, ViewerState& state) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340.0f, 0.0f), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Simulation")) {
    ImGui::End();
    return;
  }
  // Scene picker over the scene files beside the current one; a broken file keeps the old scene.
  const std::string current = std::filesystem::path(session.scene_path()).filename().string();
  if (ImGui::BeginCombo("scene", current.c_str())) {
    for (const std::string& file : state.scene_files) {
      const std::string name = std::filesystem::path(file).filename().string();
      if (ImGui::Selectable(name.c_str(), name == current)) state.requests.load = file;
    }
    ImGui::EndCombo();
  }

  if (ImGui::Button(session.playing ? "Pause" : "Play", ImVec2(70.0f, 0.0f)))
    state.requests.toggle_play = true;
  ImGui::SameLine();
  if (ImGui::Button("Step")) state.requests.step = true;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("One time step");
  ImGui::SameLine();
  if (ImGui::Button("Frame")) state.requests.frame = true;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Advance to the end of the frame (1/%g s)", session.scene().fps);
  ImGui::SameLine();
  if (ImGui::Button("Reset")) state.requests.reset = true;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Reload %s", session.scene_path().c_str());

  float speed = static_cast<float>(state.speed);
  if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic))
    state.speed = speed;

  const World& world = session.world();
  ImGui::Text("frame %d (+%d steps), t = %.3f s", session.frame(), session.step_in_frame(), world.time());

  if (!session.error().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", session.error().c_str());
    ImGui::PopStyleColor();
    if (ImGui::SmallButton("dismiss")) state.requests.clear_error = true;
  }
  ImGui::End();
}

}  // namespace weft
