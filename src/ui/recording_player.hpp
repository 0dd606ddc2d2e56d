#pragma once
// A headless recording shown in the viewer (`weft view DIR`): its frames put into a session's world
// (the cloths' positions, velocities by backward difference, the time), a timeline played at the
// recording's own speed, and the run's stats.csv. No OpenGL and no ImGui.
#include <string>

#include "io/recording_reader.hpp"
#include "ui/simulation_session.hpp"

namespace weft {

class RecordingPlayer {
 public:
  // `stats`: the run's stats.csv (empty when it has none).
  RecordingPlayer(Recording recording, StatsTable stats);

  // Throws IoError when `session`'s cloths are not the recording's (in number or vertex count).
  void check_matches(const SimulationSession& session) const;

  int frames() const { return recording_.frames; }
  int frame() const { return frame_; }
  double fps() const { return recording_.fps; }
  const std::string& folder() const { return folder_; }
  const StatsTable& stats() const { return stats_; }

  // Shows frame `frame` (clamped to the recording) in `session`'s world. Throws IoError when an
  // OBJ frame file cannot be read.
  void show(SimulationSession& session, int frame);
  // Playback at `speed` times the recording's frame rate; returns whether another frame is due
  // (show it). Stops at the last frame.
  bool advance(double wall_seconds, double speed);

  bool playing = false;

 private:
  Recording recording_;
  StatsTable stats_;
  std::string folder_;
  int frame_ = 0;
  double time_ = 0.0;  // s of recording time played, advance()'s clock
};

}  // namespace weft
