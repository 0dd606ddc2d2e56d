#pragma once
// The headless runner: simulates a scene without any window and records it to a folder
// (io/recording.hpp), with checkpoints to resume from, per-frame stats, a run summary and a
// stop with a diagnostic when the simulation goes wrong (sim/stability.hpp).
#include <string>
#include <vector>

#include "io/recording.hpp"
#include "sim/stability.hpp"

namespace weft {

struct HeadlessOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // "--set path=value"
  std::string out_dir;
  int frames = -1;     // -1: the scene's "frames"
  bool quiet = false;  // no progress output
  int threads = 1;     // threads for the solver (0: all cores)
  bool fixed_threads = false;  // never let the thread governor fall back to one thread
  RecordingFormat format = RecordingFormat::point_cache;
  bool format_given = false;  // false with resume_dir: the format of the recorded run
  int checkpoint_every = 0;  // frames between checkpoints; 0: none
  std::string resume_dir;    // continue the run recorded there (from its checkpoint)
  bool scene_given = true;   // false with resume_dir: the scene of the recorded run
  bool newton_log = false;   // DIR/newton.csv: every Newton iteration (docs/recording.md)
  StabilityLimits limits;
};

// Exit codes of a headless run.
enum ExitCode : int {
  exit_done = 0,
  exit_bad_input = 2,
  exit_diverged = 3,
  exit_output_error = 4,
  exit_interrupted = 130,
};

// Returns the process exit code (ExitCode).
int run_headless(const HeadlessOptions& options);

}  // namespace weft
