#pragma once
// `weft check DIR`: the tangle check (check/tangle_check.hpp) on every frame of a headless
// recording. Reads DIR/run.json (the resolved scene: the colliders' shapes, the frames written),
// DIR/recording.json (the cloths' names and files, mesh colliders' triangles), each cloth's rest
// OBJ and PC2 cache (or the OBJ frame files) and colliders.csv (each collider's placement per
// frame). Prints one line per tangled frame and a summary line.
#include <string>

namespace weft {

struct CheckOptions {
  std::string dir;
};

// Exit codes: 0 every frame clean, 1 some frame tangled, 2 bad or missing input (the message
// names the file and what was expected).
int run_check(const CheckOptions& options);

}  // namespace weft
