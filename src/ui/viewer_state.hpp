#pragma once
// What the viewer's panels edit and show besides the SimulationSession: display options, playback
// speed, debugging switches, the plot history and the frame's measurements. No ImGui here.
#include <string>
#include <vector>

#include "render/world_view.hpp"
#include "ui/simulation_worker.hpp"
#include "ui/stats_history.hpp"

namespace weft {

struct HoverInfo {
  bool valid = false;
  int cloth = -1;
  int vertex = -1;
};

// What the panels and keys ask of the simulation this frame; the viewer sends them to the worker.
struct SessionRequests {
  bool toggle_play = false;
  bool step = false;   // one time step
  bool frame = false;  // to the end of the frame
  bool reset = false;  // reload the scene file
  bool clear_error = false;
  std::string load;  // another scene file, if not empty
  int show_frame = -1;  // a recording's frame to show, if not negative
  int history_frame = -1;      // a kept frame to show (pauses), if not negative
  bool resume_latest = false;  // leave the history: the latest frame, playing
  bool resume_shown = false;   // go on from the history frame shown, playing
};

struct ViewerState {
  ViewOptions view;
  double speed = 1.0;                    // simulated seconds per wall second while playing
  std::vector<std::string> scene_files;  // the scene picker's list
  std::string shader_message;      // the last shader reload's error, empty if it worked

  // Requests from the panels, handled by the viewer loop.
  SessionRequests requests;
  bool reload_shaders = false;
  bool save_screenshot = false;
  bool record_frames = false;      // save every drawn frame as a PNG
  bool panels_in_pictures = false; // saved pictures include the ImGui panels

  // Measurements of the current frame, for the status line.
  StatsHistory history;
  double frames_per_second = 0.0;
  double real_time_factor = 0.0;  // simulated seconds per wall second (the worker's)
  double steps_per_second = 0.0;  // the worker's steps per wall second
  HoverInfo hover;
  HistoryRange kept_frames;               // the worker's history, as of this frame
  int scrubbed_frame = -1;                // the history frame shown, -1 when showing the latest
  std::vector<std::string> tangle_pairs;  // the shown frame's intersecting pairs, with "tangles" on
  std::string last_saved;          // the last screenshot written
};

}  // namespace weft
