#include <imgui.h>

#include <algorithm>
#include <filesystem>

#include "ui/panels.hpp"

namespace weft {

void draw_simulation_panel(const SimulationSession& session, ViewerState& state) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340.0f, 0.0f), ImGuiCond_FirstUseEver);
  // Sized to its contents: the history row and an error come and go.
  if (!ImGui::Begin("Simulation", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::End();
    return;
  }
  ImGui::PushItemWidth(220.0f);
  ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 320.0f);
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

  const HistoryRange& kept = state.kept_frames;
  if (!kept.empty()) {
    // Scrubbing pauses; the worker keeps every frame's start, the latest within --history-mb.
    int frame = state.scrubbed_frame >= 0 ? state.scrubbed_frame : kept.last;
    if (ImGui::SliderInt("history", &frame, kept.first, std::max(kept.last, kept.first + 1)))
      state.requests.history_frame = std::min(frame, kept.last);
    if (ImGui::IsItemHovered()) {
      ImGui::SetTooltip("Frames %d to %d kept (%.0f MB); drag to look back (pauses)", kept.first, kept.last,
                        kept.bytes / 1048576.0);
    }
    if (state.scrubbed_frame >= 0) {
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.3f, 1.0f), "showing frame %d from the history",
                         state.scrubbed_frame);
      if (ImGui::Button("Resume from here")) state.requests.resume_shown = true;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("Drop the later frames and go on from this one");
      ImGui::SameLine();
      if (ImGui::Button("Back to latest")) state.requests.resume_latest = true;
    }
  }

  if (!session.error().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
    ImGui::TextWrapped("%s", session.error().c_str());
    ImGui::PopStyleColor();
    if (ImGui::SmallButton("dismiss")) state.requests.clear_error = true;
  }
  ImGui::PopTextWrapPos();
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace weft
