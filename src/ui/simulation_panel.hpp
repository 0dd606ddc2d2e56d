#pragma once
// The "Simulation" ImGui window: play, pause, step and reset a SimulationSession, set its time
// step, and read its clock and cost. Call between ImGui::NewFrame() and ImGui::Render().
#include "ui/simulation_session.hpp"

namespace weft {

void draw_simulation_panel(SimulationSession& session);

}  // namespace weft
