#pragma once
// The interactive viewer (only built with WEFT_VIEWER).
#include <string>
#include <vector>

namespace weft {

struct ViewerOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // "--set path=value"
  std::string screenshot_path;         // if set: run `frames` frames, save a PNG, exit
  int frames = 0;                      // with screenshot_path: frames to simulate first
  int width = 1280, height = 720;
};

// Opens the window and runs until closed. Returns the process exit code: 0, 1 when no window
// can be opened (message on stderr naming --headless), 2 for a bad scene.
int run_viewer(const ViewerOptions& options);

}  // namespace weft
