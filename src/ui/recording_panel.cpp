#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <vector>

#include "ui/panels.hpp"

namespace weft {

namespace {

// The columns of stats.csv plotted, with their units.
struct PlottedColumn {
  const char* name;
  const char* label;
  const char* unit;
};
constexpr PlottedColumn plotted_columns[] = {
    {"kinetic_energy", "kinetic", "J"},
    {"potential_energy", "potential", "J"},
    {"contacts", "contacts", ""},
    {"newton_iterations", "Newton its", ""},
    {"unconverged_steps", "unconverged", ""},
    {"step_ms", "step", "ms"},
};

// The stats row of `frame` (rows are in frame order, one per frame from 0); -1 if none.
int row_of_frame(const StatsTable& stats, int frame) {
  const int frame_column = stats.column("frame");
  if (frame_column < 0) return -1;
  const auto found = std::lower_bound(stats.rows.begin(), stats.rows.end(), static_cast<double>(frame),
                                      [&](const std::vector<double>& row, double value) {
                                        return row[static_cast<size_t>(frame_column)] < value;
                                      });
  if (found == stats.rows.end() || (*found)[static_cast<size_t>(frame_column)] != frame) return -1;
  return static_cast<int>(found - stats.rows.begin());
}

// One column over the whole run, the shown frame's row marked by a vertical line and its value.
void plot_column(const StatsTable& stats, int column, const PlottedColumn& plotted, int row) {
  std::vector<float> values;
  values.reserve(stats.rows.size());
  for (const std::vector<double>& r : stats.rows)
    values.push_back(static_cast<float>(r[static_cast<size_t>(column)]));
  char overlay[64] = "";
  if (row >= 0)
    std::snprintf(overlay, sizeof(overlay), "%.4g %s", values[static_cast<size_t>(row)], plotted.unit);
  ImGui::PlotLines(plotted.label, values.data(), static_cast<int>(values.size()), 0, overlay, FLT_MAX,
                   FLT_MAX, ImVec2(0.0f, 45.0f));
  if (row < 0 || values.size() < 2) return;
  const ImVec2 min = ImGui::GetItemRectMin();
  const float width = ImGui::CalcItemWidth();
  const float padding = ImGui::GetStyle().FramePadding.x;
  const float x = min.x + padding + (width - 2.0f * padding) * row / static_cast<float>(values.size() - 1);
  const float bottom = min.y + 45.0f;
  ImGui::GetWindowDrawList()->AddLine(ImVec2(x, min.y), ImVec2(x, bottom), IM_COL32(255, 210, 60, 255), 1.5f);
}

}  // namespace

void draw_recording_panel(const RecordingPlayer& player, ViewerState& state) {
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->WorkSize.x - 430.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(420.0f, 0.0f), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Recording")) {
    ImGui::End();
    return;
  }
  ImGui::TextWrapped("%s", player.folder().c_str());
  const int last = player.frames() - 1;
  ImGui::Text("frame %d of 0..%d, t = %.3f s (%g frames/s)", player.frame(), last,
              player.frame() / player.fps(), player.fps());
  ImGui::PushItemWidth(-110.0f);
  int frame = player.frame();
  if (ImGui::SliderInt("frame", &frame, 0, std::max(last, 0))) state.requests.show_frame = frame;
  if (ImGui::Button("|<")) state.requests.show_frame = 0;
  ImGui::SameLine();
  if (ImGui::Button("<")) state.requests.show_frame = std::max(player.frame() - 1, 0);
  ImGui::SameLine();
  if (ImGui::Button(player.playing ? "Pause" : "Play", ImVec2(60.0f, 0.0f)))
    state.requests.toggle_play = true;
  ImGui::SameLine();
  if (ImGui::Button(">")) state.requests.show_frame = std::min(player.frame() + 1, last);
  ImGui::SameLine();
  if (ImGui::Button(">|")) state.requests.show_frame = last;
  float speed = static_cast<float>(state.speed);
  if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx", ImGuiSliderFlags_Logarithmic))
    state.speed = speed;

  ImGui::Separator();
  ImGui::Checkbox("check this frame for intersections", &state.view.tangles);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "Exact test: triangles sharing a vertex or an edge intersect when they meet anywhere else");
  if (state.view.tangles) {
    if (state.tangle_pairs.empty()) {
      ImGui::TextUnformatted("no intersecting triangle pairs");
    } else {
      ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.9f, 1.0f),
                         "%d intersecting pairs (magenta):", static_cast<int>(state.tangle_pairs.size()));
      ImGui::BeginChild("pairs", ImVec2(0.0f, 90.0f), true);
      for (const std::string& pair : state.tangle_pairs) ImGui::TextUnformatted(pair.c_str());
      ImGui::EndChild();
    }
  }

  ImGui::Separator();
  const StatsTable& stats = player.stats();
  if (stats.rows.empty()) {
    ImGui::TextDisabled("no stats.csv in the recording");
  } else {
    const int row = row_of_frame(stats, player.frame());
    for (const PlottedColumn& plotted : plotted_columns) {
      const int column = stats.column(plotted.name);
      if (column >= 0) plot_column(stats, column, plotted, row);
    }
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

}  // namespace weft
