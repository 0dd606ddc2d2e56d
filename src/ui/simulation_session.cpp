#include "ui/simulation_session.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <utility>

#include "core/error.hpp"
#include "io/scene_builder.hpp"
#include "io/scene_file.hpp"
#include "ui/session_settings.hpp"

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
  try {
    world_ = build_world(scene_);
  } catch (const SceneError& error) {
    throw naming_override(error, overrides_);
  }
  set_max_time_step(scene_.time_step);
}

SimulationSession SimulationSession::mirror() const {
  SimulationSession copy;
  copy.scene_path_ = scene_path_;
  copy.overrides_ = overrides_;
  copy.scene_ = scene_;
  copy.world_.settings = world_.settings;
  for (size_t c = 0; c < world_.cloths().size(); ++c)
    copy.world_.add_cloth(world_.cloths()[c], world_.contact_material(static_cast<int>(c)));
  for (const Collider& collider : world_.colliders()) copy.world_.add_collider(collider);
  copy.max_time_step_ = max_time_step_;
  copy.schedule_ = schedule_;
  copy.playing = playing;
  copy.pause_on_contact = pause_on_contact;
  copy.generation_ = generation_;
  copy.threads_ = threads_;
  copy.show_state_of(*this);
  return copy;
}

void SimulationSession::show_state_of(const SimulationSession& live) {
  world_.show_state_of(live.world_);
  frame_ = live.frame_;
  step_in_frame_ = live.step_in_frame_;
  error_ = live.error_;
}

SimulationSession SimulationSession::from_scene(std::string source, SceneDesc scene) {
  SimulationSession session;
  session.scene_path_ = std::move(source);
  session.scene_ = std::move(scene);
  session.world_ = build_world(session.scene_);
  session.set_max_time_step(session.scene_.time_step);
  return session;
}

void SimulationSession::show_checkpoint(const Checkpoint& checkpoint) {
  restore_checkpoint(checkpoint, world_, "the viewer's history");
  frame_ = checkpoint.frame;
  step_in_frame_ = 0;
}

void SimulationSession::restart_from(const Checkpoint& checkpoint) {
  const SessionSettings edited = read_settings(*this, VertexDrag());
  World world = build_world(scene_);
  restore_checkpoint(checkpoint, world, "the viewer's history");
  world_ = std::move(world);
  apply_settings(*this, edited);
  world_.settings.threads = threads_;
  frame_ = checkpoint.frame;
  step_in_frame_ = 0;
  time_owed_ = 0.0;
  previous_contacts_ = 0;
  error_.clear();
}

bool SimulationSession::replace_world(const std::string& scene_path, const std::vector<std::string>& overrides,
                                      const char* action) {
  try {
    SceneDesc scene = load_scene_file(scene_path, overrides);
    World world = build_world(scene);
    scene_ = std::move(scene);
    world_ = std::move(world);
  } catch (const SceneError& error) {
    error_ =
        std::string(action) + " failed, kept the current scene: " + naming_override(error, overrides).what();
    return false;
  } catch (const IoError& error) {
    error_ = std::string(action) + " failed, kept the current scene: " + error.what();
    return false;
  }
  set_max_time_step(scene_.time_step);
  world_.settings.threads = threads_;
  frame_ = 0;
  step_in_frame_ = 0;
  time_owed_ = 0.0;
  previous_contacts_ = 0;
  error_.clear();
  ++generation_;
  return true;
}

bool SimulationSession::reset() { return replace_world(scene_path_, overrides_, "reset"); }

bool SimulationSession::load(const std::string& scene_path) {
  if (!replace_world(scene_path, {}, "loading the scene")) return false;
  scene_path_ = scene_path;
  overrides_.clear();
  return true;
}

void SimulationSession::set_threads(int threads) {
  threads_ = threads > 0 ? threads : std::max(1, omp_get_num_procs());
  world_.settings.threads = threads_;
}

void SimulationSession::set_max_time_step(double max_time_step) {
  max_time_step_ = max_time_step;
  schedule_ = frame_schedule(scene_.fps, max_time_step_);
  world_.settings.time_step = schedule_.time_step;
  step_in_frame_ = std::min(step_in_frame_, schedule_.steps_per_frame - 1);
}

bool SimulationSession::advance_step() {
  if (before_step) before_step(world_);
  world_.step();
  if (++step_in_frame_ >= schedule_.steps_per_frame) {
    step_in_frame_ = 0;
    ++frame_;
  }
  if (!world_is_finite(world_)) {
    playing = false;
    std::ostringstream message;
    message << "the simulation diverged in frame " << frame_ << " (t = " << world_.time()
            << " s); reset and try a smaller time step";
    error_ = message.str();
    return false;
  }
  const int contacts = world_.last_step_stats().contacts;
  const bool first_contact = contacts > 0 && previous_contacts_ == 0;
  previous_contacts_ = contacts;
  if (pause_on_contact && first_contact && playing) {
    playing = false;
    std::ostringstream message;
    message << "paused on the first contact (" << contacts << " contacts at t = " << world_.time() << " s)";
    error_ = message.str();
    return false;
  }
  return true;
}

void SimulationSession::advance_frame() {
  // Finishes the current frame (a whole one when none is under way).
  const int start_frame = frame_;
  while (frame_ == start_frame) {
    if (!advance_step() && !world_is_finite(world_)) return;
  }
}

int SimulationSession::play(double wall_seconds, double speed, double budget_ms) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  time_owed_ += std::max(0.0, speed * wall_seconds);
  int steps = 0;
  while (playing && time_owed_ >= 0.5 * schedule_.time_step) {
    advance_step();
    time_owed_ -= schedule_.time_step;
    ++steps;
    if (std::chrono::duration<double, std::milli>(Clock::now() - start).count() > budget_ms) {
      time_owed_ = 0.0;  // behind real time: drop the debt rather than spiral
      break;
    }
  }
  if (!playing) time_owed_ = 0.0;
  return steps;
}

std::vector<std::string> list_scene_files(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.is_regular_file(error) && entry.path().extension() == ".json") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace weft
