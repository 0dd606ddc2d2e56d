#pragma once
// The headless runner: simulates a scene without any window and records it to a folder.
#include <string>
#include <vector>

namespace weft {

struct HeadlessOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // "--set path=value"
  std::string out_dir;
  int frames = -1;                     // -1: the scene's "frames"
  bool quiet = false;                  // no progress output
  int threads = 1;                     // threads for the solver (0: all cores)
};

// Returns the process exit code: 0 done, 2 bad input, 4 output error, 130 interrupted (Ctrl-C).
int run_headless(const HeadlessOptions& options);

}  // namespace weft
