#include "app/world_tangles.hpp"

#include <cstdio>

namespace weft {

TangleReport WorldTangles::check(const World& world) {
  const int num_colliders = static_cast<int>(world.colliders().size());
  collider_positions_.resize(num_colliders);
  input_ = TangleInput{};
  for (const Cloth& cloth : world.cloths()) {
    input_.cloths.push_back({cloth.model.name, &cloth.state.x, &cloth.model.triangles});
  }
  for (int k = 0; k < num_colliders; ++k) {
    const Collider& collider = world.colliders()[k];
    collider_positions_[k] = world.collider_positions(k);
    input_.colliders.push_back(
        {collider.name, &collider_positions_[k], &world.collider_surface(k).triangles});
    if (const auto solid = collider_solid_at(collider, world.time())) {
      input_.solids.push_back(*solid);
      input_.solid_collider.push_back(k);
    }
  }
  if (!held_decided_) {
    held_ = solids_holding_cloths(input_);
    held_decided_ = true;
  }
  input_.held = held_;
  return check_tangles(input_);
}

void say_if_tangled_at_start(const std::string& source, const TangleReport& report,
                             const TangleInput& input) {
  if (report.clean()) return;
  std::fprintf(stderr, "weft: %s: starts tangled: %s\n", source.c_str(),
               describe_tangles(report, input).c_str());
}

}  // namespace weft
