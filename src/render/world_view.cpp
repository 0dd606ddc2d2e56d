#include "render/world_view.hpp"

#include <algorithm>

#include "collision/collider_geometry.hpp"
#include "render/collider_mesh.hpp"

namespace weft {

WorldMeshes show_world(Renderer& renderer, const World& world, const ViewOptions& options,
                       const WorldPalette& palette) {
  renderer.clear();
  WorldMeshes meshes;
  meshes.subdivision_levels = std::clamp(options.subdivision_levels, 0, 2);
  for (const Cloth& cloth : world.cloths()) {
    LoopSubdivision subdivision =
        make_loop_subdivision(cloth.model.triangles, cloth.num_vertices(), meshes.subdivision_levels);
    // Soft bodies apart from cloth at a glance.
    const SurfaceStyle& style = cloth.model.pressure.enabled ? palette.soft_body : palette.cloth;
    meshes.cloths.push_back(renderer.add_mesh(subdivision.triangles, subdivision.apply(cloth.state.x), style));
    meshes.subdivisions.push_back(std::move(subdivision));
  }
  // Planes: a square ten scene sizes wide reads as an endless floor.
  const Eigen::AlignedBox3d bounds = world_bounds(world);
  const double scene_radius = bounds.isEmpty() ? 1.0 : 0.5 * bounds.diagonal().norm();
  meshes.scene_size = 2.0 * scene_radius;
  meshes.plane_half_size = std::max(10.0, 10.0 * scene_radius);
  meshes.plane_anchor = bounds.isEmpty() ? Vec3::Zero() : Vec3(bounds.center());
  for (const Collider& collider : world.colliders()) {
    const TriangleMesh mesh = collider_mesh(collider, meshes.plane_half_size);
    const SurfaceStyle& style = collider.shape == ColliderShape::plane ? palette.ground : palette.collider;
    const MeshHandle handle = renderer.add_mesh(mesh.triangles, mesh.positions, style);
    renderer.set_transform(handle, collider_placement(collider, meshes.plane_anchor));
    meshes.colliders.push_back(handle);
  }
  update_world(renderer, meshes, world, options);
  return meshes;
}

void update_world(Renderer& renderer, const WorldMeshes& meshes, const World& world, const ViewOptions& options) {
  MeshDisplay cloth_display;
  cloth_display.wireframe = options.wireframe;
  cloth_display.heat_map = options.strain;
  cloth_display.scalar_range = options.strain_range;
  for (size_t k = 0; k < meshes.cloths.size(); ++k) {
    const Cloth& cloth = world.cloths()[k];
    const LoopSubdivision& subdivision = meshes.subdivisions[k];
    renderer.update_positions(meshes.cloths[k], subdivision.apply(cloth.state.x));
    if (options.strain) renderer.update_scalars(meshes.cloths[k], subdivision.apply(vertex_strain(cloth.model, cloth.state.x)));
    renderer.set_display(meshes.cloths[k], cloth_display);
  }
  MeshDisplay collider_display;
  collider_display.visible = options.colliders;
  collider_display.cull_front = options.cutaway;
  for (size_t k = 0; k < meshes.colliders.size(); ++k) {
    renderer.set_transform(meshes.colliders[k],
                           collider_placement(world.colliders()[k], meshes.plane_anchor, world.time()));
    renderer.set_display(meshes.colliders[k], collider_display);
  }
}

void update_bvhs(WorldMeshes& meshes, const World& world) {
  meshes.cloth_bvhs.resize(world.cloths().size());
  for (size_t k = 0; k < world.cloths().size(); ++k) {
    const Cloth& cloth = world.cloths()[k];
    Bvh& bvh = meshes.cloth_bvhs[k];
    const bool fresh = bvh.num_vertices() != cloth.num_vertices() ||
                       bvh.num_triangles() != static_cast<int>(cloth.model.triangles.cols());
    if (fresh || bvh.needs_rebuild()) {
      bvh.build(cloth.state.x, cloth.model.triangles, cloth.model.thickness);
    } else {
      bvh.refit(cloth.state.x, cloth.model.thickness);
    }
  }
}

void build_overlay(DebugOverlay& overlay, const World& world, const WorldMeshes& meshes, const ViewOptions& options,
                   const std::vector<ContactRecord>& contacts, const WorldPalette& palette) {
  overlay.clear();
  if (options.ground_grid) {
    for (const Collider& collider : world.colliders()) {
      if (collider.shape != ColliderShape::plane) continue;
      const double half_size = 0.3 * meshes.plane_half_size;
      add_ground_grid(overlay, collider, meshes.plane_anchor, half_size, 0.25, palette.grid);
    }
  }
  if (options.boxes) {
    for (const Bvh& bvh : meshes.cloth_bvhs) {
      for (const Eigen::AlignedBox3d& box : bvh_boxes_at_depth(bvh, options.box_depth)) {
        overlay.add_box(box, palette.cloth_box);
      }
    }
    for (size_t k = 0; k < world.colliders().size(); ++k) {
      overlay.add_box(collider_bounds(world, static_cast<int>(k)), palette.collider_box);
    }
  }
  if (options.pins) {
    for (const Cloth& cloth : world.cloths()) add_pins(overlay, cloth, palette.pin);
  }
  if (options.contacts) {
    add_contacts(overlay, contacts, options.impulse_scale, options.max_arrow_length * meshes.scene_size);
  }
}

Eigen::VectorXd vertex_strain(const ClothModel& model, const Positions& x) {
  const SpringSet& springs = model.springs;
  const int n = static_cast<int>(x.cols());
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(n);
  const bool has_structural = springs.count(SpringKind::structural) > 0;
  const int begin = has_structural ? springs.kind_begin[0] : 0;
  const int end = has_structural ? springs.kind_begin[1] : springs.size();
  for (int s = begin; s < end; ++s) {
    const int i = springs.vertices(0, s), j = springs.vertices(1, s);
    if (springs.rest_length[s] <= 0.0) continue;
    const double strain = (x.col(j) - x.col(i)).norm() / springs.rest_length[s] - 1.0;
    sum[i] += strain;
    sum[j] += strain;
    count[i] += 1.0;
    count[j] += 1.0;
  }
  return (count.array() > 0.0).select(sum.array() / count.array().max(1.0), 0.0).matrix();
}

Eigen::AlignedBox3d collider_bounds(const World& world, int collider) {
  Eigen::AlignedBox3d box;
  const Collider& solid = world.colliders()[collider];
  if (solid.shape == ColliderShape::plane) return box;
  if (solid.shape == ColliderShape::sphere) {  // exact, where the tessellation sticks out a little
    const Vec3 center = solid.motion.place(solid.center, world.time());
    return {center - Vec3::Constant(solid.radius), center + Vec3::Constant(solid.radius)};
  }
  const Positions x = world.collider_positions(collider);
  for (int v = 0; v < x.cols(); ++v) box.extend(Vec3(x.col(v)));
  return box;
}

Eigen::AlignedBox3d world_bounds(const World& world) {
  Eigen::AlignedBox3d box;
  for (const Cloth& cloth : world.cloths()) {
    for (int i = 0; i < cloth.num_vertices(); ++i) box.extend(Vec3(cloth.state.x.col(i)));
  }
  for (size_t k = 0; k < world.colliders().size(); ++k) box.extend(collider_bounds(world, static_cast<int>(k)));
  // A plane adds the point of it nearest the rest of the scene: a floor below a hanging cloth
  // brings the space the cloth will fall through into view.
  if (box.isEmpty()) return box;
  const Vec3 center = box.center();
  for (const Collider& collider : world.colliders()) {
    if (collider.shape != ColliderShape::plane) continue;
    const Vec3 normal = collider.normal.normalized();
    box.extend(Vec3(center - normal.dot(center - collider.center) * normal));
  }
  return box;
}

}  // namespace weft
