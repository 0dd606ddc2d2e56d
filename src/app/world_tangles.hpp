#pragma once
// The tangle check (check/tangle_check.hpp) of a World's state, or of a recorded frame: the
// cloths, the colliders' surfaces posed at the state's time and the analytic colliders' solids.
// Meshes and open cylinders have no inside (check/solid_distance.hpp says why), so only their
// surfaces are checked.
#include <string>
#include <vector>

#include "app/collider_solid.hpp"
#include "check/tangle_check.hpp"
#include "sim/world.hpp"

namespace weft {

// Checks a World between steps; keeps the posed colliders' positions between calls.
class WorldTangles {
 public:
  // Checks the world's state; the first call decides which solids hold which cloths
  // (solids_holding_cloths), and later calls keep that.
  TangleReport check(const World& world);
  // What the last check read (names, surfaces, solids), for describe_tangles.
  const TangleInput& input() const { return input_; }

 private:
  std::vector<Positions> collider_positions_;
  TangleInput input_;
  std::vector<std::vector<char>> held_;
  bool held_decided_ = false;
};

// The first frame's check said on stderr, when it is tangled: "weft: SOURCE: starts tangled: ...".
void say_if_tangled_at_start(const std::string& source, const TangleReport& report, const TangleInput& input);

}  // namespace weft
