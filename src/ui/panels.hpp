#pragma once
// The viewer's Dear ImGui windows. Call between ImGui::NewFrame() and ImGui::Render().
#include "ui/recording_player.hpp"
#include "ui/simulation_session.hpp"
#include "ui/viewer_state.hpp"

namespace weft {

// Play, pause, step, reset, speed, the scene picker and any error; what they ask for goes into
// state.requests.
void draw_simulation_panel(const SimulationSession& session, ViewerState& state);
// Integrator, time step, sub-steps, Newton and adaptive-stepping settings, applied live.
void draw_solver_panel(SimulationSession& session);
// Springs, damping, density, thickness, friction, applied live.
void draw_material_panel(SimulationSession& session);
// Bounding boxes, contacts, pause on first contact, display options, shader reload.
void draw_debug_panel(SimulationSession& session, ViewerState& state);
// A recording's timeline (`weft view DIR`): the frame slider, play at the recording's speed, the
// exact intersection check of the shown frame with its pairs listed, and stats.csv's columns over
// the run with the shown frame marked.
void draw_recording_panel(const RecordingPlayer& player, ViewerState& state);
// Energies, time per phase and Newton iterations over the last frames.
void draw_plots_panel(const ViewerState& state);
// One line at the bottom: sizes, contacts, ms per step by phase, the window's frames per second,
// the simulation's steps per second and real-time factor.
void draw_status_line(const SimulationSession& session, const ViewerState& state);

}  // namespace weft
