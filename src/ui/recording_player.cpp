#include "ui/recording_player.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace weft {

RecordingPlayer::RecordingPlayer(Recording recording, StatsTable stats)
    : recording_(std::move(recording)), stats_(std::move(stats)), folder_(recording_.dir.string()) {}

void RecordingPlayer::check_matches(const SimulationSession& session) const {
  const std::string manifest = (recording_.dir / "recording.json").string();
  const std::vector<Cloth>& cloths = session.world().cloths();
  if (cloths.size() != recording_.cloths.size()) {
    throw IoError(manifest + ": \"cloths\": run.json's scene builds " + std::to_string(cloths.size()) +
                  " cloths, the recording has " + std::to_string(recording_.cloths.size()));
  }
  for (size_t c = 0; c < cloths.size(); ++c) {
    if (cloths[c].num_vertices() != recording_.cloths[c].vertices) {
      throw IoError(manifest + ": cloth \"" + recording_.cloths[c].name + "\": run.json's scene builds " +
                    std::to_string(cloths[c].num_vertices()) + " vertices, the recording has " +
                    std::to_string(recording_.cloths[c].vertices));
    }
  }
}

void RecordingPlayer::show(SimulationSession& session, int frame) {
  frame = std::clamp(frame, 0, recording_.frames - 1);
  if (frame != frame_) time_ = frame / recording_.fps;  // a jump; advance() keeps its own clock
  frame_ = frame;
  const std::vector<Positions> positions = cloth_positions(recording_, frame_);
  const std::vector<Positions> previous =
      frame_ > 0 ? cloth_positions(recording_, frame_ - 1) : std::vector<Positions>();
  World& world = session.world();
  for (size_t c = 0; c < positions.size(); ++c) {
    ClothState& state = world.cloths()[c].state;
    state.x = positions[c];
    if (previous.empty()) {
      state.v.setZero();
    } else {
      state.v = (positions[c] - previous[c]) * recording_.fps;
    }
  }
  world.set_time(frame_ / recording_.fps);
}

bool RecordingPlayer::advance(double wall_seconds, double speed) {
  if (!playing) return false;
  time_ += wall_seconds * speed;
  const int due =
      std::min(static_cast<int>(std::floor(time_ * recording_.fps + 1e-9)), recording_.frames - 1);
  if (due >= recording_.frames - 1) playing = false;
  if (due == frame_) return false;
  frame_ = due;
  return true;
}

}  // namespace weft
