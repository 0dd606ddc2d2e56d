#pragma once
// Shows a World through a Renderer: registers one mesh per cloth and per collider, then pushes the
// cloths' new positions (and the colliders' placements) each frame.
#include <vector>

#include <Eigen/Geometry>

#include "render/renderer.hpp"
#include "sim/world.hpp"

namespace weft {

struct WorldPalette {
  SurfaceStyle cloth{{0.95f, 0.52f, 0.18f}, {0.22f, 0.42f, 0.85f}, 0.12f, 24.0f};  // warm front, blue back
  SurfaceStyle collider{{0.62f, 0.62f, 0.62f}, {0.38f, 0.38f, 0.38f}, 0.25f, 48.0f};
  SurfaceStyle ground{{0.40f, 0.40f, 0.41f}, {0.22f, 0.22f, 0.22f}, 0.05f, 16.0f, 0.5f};  // planes
};

// The renderer's meshes of one World, in the order of world.cloths() and world.colliders().
struct WorldMeshes {
  std::vector<MeshHandle> cloths;
  std::vector<MeshHandle> colliders;
  Vec3 plane_anchor = Vec3::Zero();  // planes are drawn as squares around this point's projection
};

// Clears the renderer and registers the world's cloths and colliders.
WorldMeshes show_world(Renderer& renderer, const World& world, const WorldPalette& palette = {});

// Pushes the cloths' current positions and the colliders' current placements.
void update_world(Renderer& renderer, const WorldMeshes& meshes, const World& world);

// Box around the cloths and the bounded colliders, extended to each plane's point nearest its centre.
Eigen::AlignedBox3d world_bounds(const World& world);

}  // namespace weft
