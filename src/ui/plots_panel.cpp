#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "ui/panels.hpp"

namespace weft {

namespace {

void plot(const char* label, const Series& series, const char* unit) {
  const std::vector<float>& values = series.values();
  char overlay[64];
  std::snprintf(overlay, sizeof(overlay), "%.4g %s", series.last(), unit);
  ImGui::PlotLines(label, values.data(), static_cast<int>(values.size()), 0, overlay, 0.0f,
                   std::max(series.max() * 1.1f, 1e-6f), ImVec2(0.0f, 50.0f));
}

}  // namespace

void draw_plots_panel(const ViewerState& state) {
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->WorkSize.x - 360.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(350.0f, 0.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowCollapsed(true, ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Plots")) {
    ImGui::End();
    return;
  }
  // Plots as wide as the window leaves beside the longest label.
  ImGui::PushItemWidth(-(ImGui::CalcTextSize("prepare collisions").x + ImGui::GetStyle().ItemInnerSpacing.x));
  const StatsHistory& history = state.history;
  plot("kinetic", history.kinetic, "J");
  // Potential energy (gravity included) can be negative: let the plot pick its own range.
  const std::vector<float>& potential = history.potential.values();
  char overlay[64];
  std::snprintf(overlay, sizeof(overlay), "%.4g J", history.potential.last());
  ImGui::PlotLines("potential", potential.data(), static_cast<int>(potential.size()), 0, overlay, FLT_MAX, FLT_MAX,
                   ImVec2(0.0f, 50.0f));
  plot("integrate", history.integrate_ms, "ms");
  plot("collisions", history.collisions_ms, "ms");
  plot("prepare collisions", history.prepare_collisions_ms, "ms");
  plot("Newton its", history.newton_iterations, "");
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace weft
