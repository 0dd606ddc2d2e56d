#include "app/check_recording.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "app/collider_solid.hpp"
#include "check/tangle_check.hpp"
#include "core/error.hpp"
#include "io/recording_reader.hpp"

namespace weft {

int run_check(const CheckOptions& options) {
  try {
    Recording recording = read_recording(options.dir);
    int tangled_frames = 0, first_tangled = -1, most_pairs = 0, most_inside = 0;
    std::vector<Positions> posed(recording.colliders.size());
    std::vector<std::vector<char>> held;  // decided at frame 0
    for (int frame = 0; frame < recording.frames; ++frame) {
      const std::vector<Positions> positions = cloth_positions(recording, frame);
      TangleInput input;
      for (size_t c = 0; c < recording.cloths.size(); ++c) {
        input.cloths.push_back({recording.cloths[c].name, &positions[c], &recording.cloths[c].triangles});
      }
      for (size_t k = 0; k < recording.colliders.size(); ++k) {
        const RecordedCollider& recorded = recording.colliders[k];
        const Placement& placement = recording.placements[frame][k];
        posed[k] = placement.rotation * recorded.surface.positions;
        posed[k].colwise() += placement.translation;
        input.colliders.push_back({recorded.collider.name, &posed[k], &recorded.surface.triangles});
        if (const auto solid = collider_solid(recorded.collider, placement.rotation, placement.translation)) {
          input.solids.push_back(*solid);
          input.solid_collider.push_back(static_cast<int>(k));
        }
      }
      TangleReport report;
      try {
        if (frame == 0) held = solids_holding_cloths(input);
        input.held = held;
        report = check_tangles(input);
      } catch (const std::invalid_argument& error) {
        throw IoError((recording.dir / "recording.json").string() + ": frame " + std::to_string(frame) +
                      ": " + error.what());
      }
      if (report.clean()) continue;
      if (tangled_frames++ == 0) first_tangled = frame;
      most_pairs = std::max(most_pairs, report.intersecting_pairs);
      most_inside = std::max(most_inside, report.vertices_inside_colliders);
      std::printf("frame %d (t = %.4g s): tangled: %s\n", frame, frame / recording.fps,
                  describe_tangles(report, input).c_str());
    }
    if (tangled_frames == 0) {
      std::printf("%s: %d frames checked, all clean\n", options.dir.c_str(), recording.frames);
      return 0;
    }
    std::printf(
        "%s: %d frames checked, %d tangled (first: frame %d; at most %d intersecting triangle pairs and %d "
        "vertices inside colliders in a frame)\n",
        options.dir.c_str(), recording.frames, tangled_frames, first_tangled, most_pairs, most_inside);
    return 1;
  } catch (const IoError& error) {
    std::fprintf(stderr, "weft check: %s\n", error.what());
    return 2;
  }
}

}  // namespace weft
