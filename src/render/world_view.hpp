#pragma once
// Shows a World through a Renderer: registers one mesh per cloth (Loop-subdivided if asked) and per
// collider, then pushes the cloths' new positions (and the colliders' placements) each frame; fills
// the debug overlay (bounding boxes, pins, ground grid, contacts) from the World.
#include <vector>

#include <Eigen/Geometry>

#include "collision/bvh.hpp"
#include "render/debug_overlay.hpp"
#include "render/loop_subdivision.hpp"
#include "render/renderer.hpp"
#include "sim/world.hpp"

namespace weft {

struct WorldPalette {
  SurfaceStyle cloth{{0.95f, 0.52f, 0.18f}, {0.22f, 0.42f, 0.85f}, 0.12f, 24.0f};  // warm front, blue back
  SurfaceStyle soft_body{{0.30f, 0.78f, 0.42f}, {0.16f, 0.45f, 0.26f}, 0.2f, 32.0f};  // green: cloths with pressure
  SurfaceStyle collider{{0.62f, 0.62f, 0.62f}, {0.38f, 0.38f, 0.38f}, 0.25f, 48.0f};
  SurfaceStyle ground{{0.40f, 0.40f, 0.41f}, {0.22f, 0.22f, 0.22f}, 0.05f, 16.0f, 0.5f};  // planes
  Color cloth_box{0.7f, 0.45f, 1.0f};  // violet, apart from the pink pins
  Color collider_box{0.3f, 0.75f, 1.0f};
  Color pin{0.9f, 0.1f, 0.55f};
  Color grid{0.55f, 0.56f, 0.58f};
};

// What the view shows; the viewer's panels edit it.
struct ViewOptions {
  int subdivision_levels = 0;     // Loop subdivision rounds of the displayed cloth (0 to 2)
  bool wireframe = false;         // cloth edges (of the displayed, possibly subdivided, mesh)
  bool strain = false;            // heat map of the structural springs' strain
  float strain_range = 0.1f;      // strain shown at full colour
  bool boxes = false;             // bounding-volume hierarchy boxes at box_depth
  int box_depth = 0;              // 0: one box per cloth and collider
  bool contacts = true;           // contact points and impulse arrows
  double impulse_scale = 200.0;   // m of arrow per N s of impulse, unless that is too long:
  double max_arrow_length = 0.1;  // the longest arrow, as a fraction of the scene's size
  bool pins = true;               // pinned vertices as dots
  bool ground_grid = true;        // grid lines on plane colliders
  bool colliders = true;
  bool cutaway = false;           // colliders without the faces turned to the camera: the inside of
                                  // a closed collider (a drum) shows through its near wall
  bool tangles = false;           // the shown frame's intersecting triangle pairs (the viewer's exact
                                  // check; on at the start of a scene that starts tangled)
};

// The renderer's meshes of one World, in the order of world.cloths() and world.colliders().
struct WorldMeshes {
  std::vector<MeshHandle> cloths;
  std::vector<LoopSubdivision> subdivisions;  // per cloth
  std::vector<MeshHandle> colliders;
  Vec3 plane_anchor = Vec3::Zero();  // planes are drawn as squares around this point's projection
  double plane_half_size = 10.0;
  double scene_size = 1.0;           // m, the diagonal of world_bounds() when registered
  int subdivision_levels = 0;        // what the cloth meshes were built with
  // One hierarchy of boxes per cloth, built like the collision module's (swept by nothing,
  // inflated by the cloth's thickness), refitted by update_bvhs() while boxes are shown.
  std::vector<Bvh> cloth_bvhs;
};

// Clears the renderer and registers the world's cloths and colliders.
WorldMeshes show_world(Renderer& renderer, const World& world, const ViewOptions& options = {},
                       const WorldPalette& palette = {});

// Pushes the cloths' current positions (and strains when shown), the colliders' placements, and
// the display options.
void update_world(Renderer& renderer, const WorldMeshes& meshes, const World& world, const ViewOptions& options = {});

// Builds (first call, after a scene change, or when refitting has made it loose) or refits the
// hierarchy of each cloth at its current positions.
void update_bvhs(WorldMeshes& meshes, const World& world);

// Rebuilds `overlay` from the world: boxes (of meshes.cloth_bvhs: call update_bvhs() first), pins,
// ground grid, and `contacts` (e.g. world.contacts()) when shown.
void build_overlay(DebugOverlay& overlay, const World& world, const WorldMeshes& meshes, const ViewOptions& options,
                   const std::vector<ContactRecord>& contacts, const WorldPalette& palette = {});

// Strain of each vertex: the mean of (length / rest length - 1) over its structural springs
// (all springs if it has none of that kind); 0 for a vertex on no spring.
Eigen::VectorXd vertex_strain(const ClothModel& model, const Positions& x);

// Box around the cloths and the bounded colliders, extended to each plane's point nearest its centre.
Eigen::AlignedBox3d world_bounds(const World& world);

// Box around collider `collider` where it is now (its surface mesh posed at world.time()); empty
// for a plane, which is unbounded.
Eigen::AlignedBox3d collider_bounds(const World& world, int collider);

}  // namespace weft
