#include <imgui.h>

#include "ui/panels.hpp"

namespace weft {

void draw_status_line(const SimulationSession& session, const ViewerState& state) {
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  const float height = ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().WindowPadding.y;
  ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x, viewport->WorkPos.y + viewport->WorkSize.y - height));
  ImGui::SetNextWindowSize(ImVec2(viewport->WorkSize.x, height));
  ImGui::SetNextWindowBgAlpha(0.6f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                 ImGuiWindowFlags_NoNav;
  if (ImGui::Begin("##status", nullptr, flags)) {
    const World& world = session.world();
    int vertices = 0;
    for (const Cloth& cloth : world.cloths()) {
      vertices += cloth.num_vertices();
    }
    const StepStats& stats = world.last_step_stats();
    if (!session.playing) {
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.3f, 1.0f), "Paused: Space or Play runs it");
      ImGui::SameLine();
      ImGui::TextUnformatted("|");
      ImGui::SameLine();
    }
    ImGui::Text(
        "%d vertices | %d contacts | step %.1f ms (integrate %.1f, collisions %.1f) | %d "
        "%s: %.1f steps/s, %.2fx real time | window %.0f fps",
        vertices, stats.contacts, stats.total_ms, stats.integrate_ms, stats.collisions_ms, session.threads(),
        session.threads() == 1 ? "thread" : "threads", state.steps_per_second, state.real_time_factor,
        state.frames_per_second);
    if (stats.unconverged_steps > 0) {  // the last step's implicit solve stopped short of its tolerance
      ImGui::SameLine();
      ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.2f, 1.0f), "| Newton unconverged (residual %.2g m/s)",
                         stats.residual);
    }
    if (stats.collision.held_pins > 0) {  // the collision response's last resort stopped pins on their script
      ImGui::SameLine();
      ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.2f, 1.0f), "| %d pins held back", stats.collision.held_pins);
    }
    if (state.hover.valid) {
      const Cloth& cloth = world.cloths()[static_cast<size_t>(state.hover.cloth)];
      const int v = state.hover.vertex;
      ImGui::SameLine();
      ImGui::Text("| cloth %d vertex %d%s", state.hover.cloth, v,
                  cloth.model.inverse_mass[v] == 0.0 ? " (pinned)" : "");
    }
  }
  ImGui::End();
}

}  // namespace weft
