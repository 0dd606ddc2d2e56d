#include "ui/simulation_session.hpp"

#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"

namespace weft {

namespace {

bool world_is_finite(const World& world) {
  for (const Cloth& cloth : world.cloths()) {
    if (!cloth.state.x.allFinite()) return false;
  }
  return true;
}

}  // namespace

SimulationSession::SimulationSession(std::string scene_path, std::vector<std::string> overrides)
    : scene_path_(std::move(scene_path)), overrides_(std::move(overrides)) {
  scene_ = load_scene_file(scene_path_, overrides_);
  world_ = build_world(scene_);
  set_max_time_step(scene_.time_step);
}

bool SimulationSession::reset() {
  try {
    SceneDesc scene = load_scene_file(scene_path_, overrides_);
    World world = build_world(scene);
    scene_ = std::move(scene);
    world_ = std::move(world);
  } catch (const SceneError& error) {
    error_ = std::string("reset failed, kept the current scene: ") + error.what();
    return false;
  } catch (const IoError& error) {
    error_ = std::string("reset failed, kept the current scene: ") + error.what();
    return false;
  }
  set_max_time_step(scene_.time_step);
  frame_ = 0;
  error_.clear();
  ++generation_;
  return true;
}

void SimulationSession::set_max_time_step(double max_time_step) {
  max_time_step_ = max_time_step;
  schedule_ = frame_schedule(scene_.fps, max_time_step_);
  world_.settings.time_step = schedule_.time_step;
}

void SimulationSession::advance_frame() {
  for (int step = 0; step < schedule_.steps_per_frame; ++step) world_.step();
  ++frame_;
  if (!world_is_finite(world_)) {
    playing = false;
    std::ostringstream message;
    message << "the simulation diverged in frame " << frame_ << " (t = " << world_.time()
            << " s); reset and try a smaller time step";
    error_ = message.str();
  }
}

}  // namespace weft
