#pragma once
// The interactive viewer (only built with WEFT_VIEWER).
#include <string>
#include <vector>

namespace weft {

struct ViewerOptions {
  std::string scene_path;
  std::string recording_dir;           // if set: show this headless recording (`weft view DIR`)
  int recording_frame = 0;             // with recording_dir: the frame shown first (--frame)
  std::vector<std::string> overrides;  // "--set path=value"
  std::string screenshot_path;         // if set: run `frames` frames, save a PNG, exit
  int frames = 0;                      // with screenshot_path: frames to simulate first
  std::string record_dir;              // if set: save every drawn frame as DIR/frame_NNNNN.png
  std::vector<std::string> show;       // display switches (display_switch_names in io/scene_file.hpp),
                                       // applied after the scene's "view": {"show": [...]}
  std::vector<std::string> open_panels;  // ImGui windows shown expanded from the start (by title)
  int box_depth = 0;                   // bounding-box depth with "boxes"
  int subdivision = 0;                 // Loop subdivision levels of the displayed cloth (0 to 2)
  bool test_contacts = false;          // draw synthetic contacts (tests the contact display path)
  bool play = false;                   // start playing
  int history_mb = 256;                // memory for the frames kept to look back through (0: none)
  double quit_after_seconds = 0.0;     // > 0: close after this much wall time
  std::string frame_times_path;        // if set: each drawn frame's times, written on closing
  int width = 1280, height = 720;
  int threads = 1;  // solver threads (--threads; 0: all cores)
};

// Opens the window and runs until closed. Returns the process exit code: 0, 1 when no window
// can be opened (message on stderr naming --headless), 2 for a bad scene, recording or option, 4 when a
// screenshot cannot be written, 5 when a screenshot run's drawing raised an OpenGL error.
int run_viewer(const ViewerOptions& options);

}  // namespace weft
