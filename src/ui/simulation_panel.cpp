#include "ui/simulation_panel.hpp"

#include <imgui.h>

#include <algorithm>

namespace weft {

void draw_simulation_panel(SimulationSession& session) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330.0f, 0.0f), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Simulation")) {
    ImGui::End();
    return;
  }
  ImGui::TextUnformatted(session.scene().name.c_str());

  if (ImGui::Button(session.playing ? "Pause" : "Play", ImVec2(70.0f, 0.0f)))
    session.playing = !session.playing;
  ImGui::SameLine();
  if (ImGui::Button("Step")) session.advance_frame();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Advance one frame (1/%g s)", session.scene().fps);
  ImGui::SameLine();
  if (ImGui::Button("Reset")) session.reset();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Reload %s", session.scene_path().c_str());

  // The largest step, on a log scale from 10 us to one frame.
  const float frame_time = static_cast<float>(1.0 / session.scene().fps);
  float max_time_step = static_cast<float>(session.max_time_step());
  if (ImGui::SliderFloat("time step (s)", &max_time_step, 1e-5f, frame_time, "%.2e",
                         ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoRoundToFormat)) {
    session.set_max_time_step(
        std::clamp(static_cast<double>(max_time_step), 1e-5, 1.0 / session.scene().fps));
  }

  const World& world = session.world();
  ImGui::Text("frame %d, t = %.3f s", session.frame(), world.time());
  ImGui::Text("%d steps of %.3g s per frame", session.schedule().steps_per_frame,
              session.schedule().time_step);
  ImGui::Text("%.3f ms per step (%d contacts)", world.last_step_stats().total_ms,
              world.last_step_stats().contacts);

  if (!session.error().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", session.error().c_str());
    ImGui::PopStyleColor();
  }
  ImGui::End();
}

}  // namespace weft
