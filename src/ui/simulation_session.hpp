#pragma once
// What the viewer's controls act on: a scene file, the World built from it, play/pause, the
// largest time step and real-time playback (ui/simulation_worker.hpp steps it on its own
// thread). No OpenGL and no ImGui, so it runs anywhere.
#include <functional>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "sim/scene_desc.hpp"
#include "sim/world.hpp"

namespace weft {

class SimulationSession {
 public:
  // Loads and builds the scene; throws SceneError or IoError.
  SimulationSession(std::string scene_path, std::vector<std::string> overrides);
  // Builds a scene already read (a recording's run.json); `source` names it in messages. Such a
  // session is shown, not reset (reset() would read `source` as a scene file). Throws SceneError.
  static SimulationSession from_scene(std::string source, SceneDesc scene);

  // A copy to draw from: the same scene, settings, cloths and colliders, and this session's shown
  // state (show_state_of). It is not meant to be stepped; its settings are for panels to edit.
  SimulationSession mirror() const;
  // Takes in what `live` (this mirror's origin, same generation) shows: its world's state
  // (World::show_state_of), frame, step within it and error.
  void show_state_of(const SimulationSession& live);

  // Shows a checkpoint of this session's world (a frame of the viewer's history): its state in
  // the world, at its frame. For a mirror, which is drawn and not stepped. Throws IoError when the
  // world does not match.
  void show_checkpoint(const Checkpoint& checkpoint);
  // Goes on from a checkpoint of this session's world: the world rebuilt from the scene as loaded
  // (not the file), as a resumed headless run, with the checkpoint's state, its frame, and the
  // settings and materials edited since. The generation stays: views keep their meshes.
  void restart_from(const Checkpoint& checkpoint);

  // Reloads the scene file and rebuilds the world. On failure keeps the current world, keeps the
  // message in error(), and returns false.
  bool reset();
  // Loads another scene file (the overrides are dropped). On failure keeps the current scene and
  // world, puts the message in error(), and returns false.
  bool load(const std::string& scene_path);

  // Advances one frame of 1/fps simulated seconds in equal steps no longer than max_time_step().
  // Stops playing, with a message in error(), if a position stops being finite.
  void advance_frame();
  // Advances one time step (a frame is steps_per_frame of them). Returns false if it stopped
  // playback (divergence, or the first contact with pause_on_contact).
  bool advance_step();
  // Real-time playback: owes `speed` x `wall_seconds` of simulated time and takes steps until the
  // debt is paid or `budget_ms` of wall time is spent; a debt the budget cannot pay is dropped,
  // so a heavy scene runs slower than real time instead of freezing the UI. Returns the steps taken.
  int play(double wall_seconds, double speed, double budget_ms);

  // Solver threads for this and every later world (a reset or another scene keeps them): the
  // viewer's --threads, 0 for all cores. Results are the same on any count.
  void set_threads(int threads);
  int threads() const { return world_.settings.threads; }
  // Largest time step (s); the frame is cut into frame_schedule(fps, max_time_step) steps.
  double max_time_step() const { return max_time_step_; }
  void set_max_time_step(double max_time_step);
  const FrameSchedule& schedule() const { return schedule_; }

  bool playing = false;
  bool pause_on_contact = false;  // stop playing on the first step that finds contacts after none
  // Called before every step (e.g. to refresh the mouse spring's external force).
  std::function<void(World&)> before_step;

  World& world() { return world_; }
  const World& world() const { return world_; }
  const SceneDesc& scene() const { return scene_; }
  const std::string& scene_path() const { return scene_path_; }
  int frame() const { return frame_; }
  // Steps done in the current, unfinished frame.
  int step_in_frame() const { return step_in_frame_; }
  // The last reset failure, divergence or contact pause, empty if none.
  const std::string& error() const { return error_; }
  void clear_error() { error_.clear(); }
  // Changes whenever the world is replaced, so views know to register it again.
  int generation() const { return generation_; }

 private:
  SimulationSession() = default;
  bool replace_world(const std::string& scene_path, const std::vector<std::string>& overrides,
                     const char* action);

  std::string scene_path_;
  std::vector<std::string> overrides_;
  SceneDesc scene_;
  World world_;
  double max_time_step_ = 0.0;
  FrameSchedule schedule_;
  int frame_ = 0;
  int step_in_frame_ = 0;
  double time_owed_ = 0.0;  // s of simulated time play() still has to take
  int previous_contacts_ = 0;
  std::string error_;
  int generation_ = 0;
  int threads_ = 1;  // set_threads
};

// The scene files (*.json) in `folder`, sorted by name; empty if it cannot be listed.
std::vector<std::string> list_scene_files(const std::string& folder);

}  // namespace weft
