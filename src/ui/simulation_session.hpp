#pragma once
// What the viewer's controls act on: a scene file, the World built from it, play/pause and the
// largest time step. No OpenGL and no ImGui, so it runs anywhere.
#include <string>
#include <vector>

#include "sim/scene_desc.hpp"
#include "sim/world.hpp"

namespace weft {

class SimulationSession {
 public:
  // Loads and builds the scene; throws SceneError or IoError.
  SimulationSession(std::string scene_path, std::vector<std::string> overrides);

  // Reloads the scene file and rebuilds the world. On failure keeps the current world, keeps the
  // message in error(), and returns false.
  bool reset();
  // Advances one frame of 1/fps simulated seconds in equal steps no longer than max_time_step().
  // Stops playing, with a message in error(), if a position stops being finite.
  void advance_frame();

  // Largest time step (s); the frame is cut into frame_schedule(fps, max_time_step) steps.
  double max_time_step() const { return max_time_step_; }
  void set_max_time_step(double max_time_step);
  const FrameSchedule& schedule() const { return schedule_; }

  bool playing = false;

  World& world() { return world_; }
  const World& world() const { return world_; }
  const SceneDesc& scene() const { return scene_; }
  const std::string& scene_path() const { return scene_path_; }
  int frame() const { return frame_; }
  // The last reset failure or divergence, empty if none.
  const std::string& error() const { return error_; }
  // Changes whenever reset() replaces the world, so views know to register it again.
  int generation() const { return generation_; }

 private:
  std::string scene_path_;
  std::vector<std::string> overrides_;
  SceneDesc scene_;
  World world_;
  double max_time_step_ = 0.0;
  FrameSchedule schedule_;
  int frame_ = 0;
  std::string error_;
  int generation_ = 0;
};

}  // namespace weft
