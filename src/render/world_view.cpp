#include "render/world_view.hpp"

#include <algorithm>

#include "collision/collider_geometry.hpp"
#include "render/collider_mesh.hpp"

namespace weft {

WorldMeshes show_world(Renderer& renderer, const World& world, const WorldPalette& palette) {
  renderer.clear();
  WorldMeshes meshes;
  for (const Cloth& cloth : world.cloths()) {
    meshes.cloths.push_back(renderer.add_mesh(cloth.model.triangles, cloth.state.x, palette.cloth));
  }
  // Planes: a square ten scene sizes wide reads as an endless floor.
  const Eigen::AlignedBox3d bounds = world_bounds(world);
  const double scene_radius = bounds.isEmpty() ? 1.0 : 0.5 * bounds.diagonal().norm();
  const double plane_half_size = std::max(10.0, 10.0 * scene_radius);
  meshes.plane_anchor = bounds.isEmpty() ? Vec3::Zero() : Vec3(bounds.center());
  for (const Collider& collider : world.colliders()) {
    const TriangleMesh mesh = collider_mesh(collider, plane_half_size);
    const SurfaceStyle& style = collider.shape == ColliderShape::plane ? palette.ground : palette.collider;
    const MeshHandle handle = renderer.add_mesh(mesh.triangles, mesh.positions, style);
    renderer.set_transform(handle, collider_placement(collider, meshes.plane_anchor));
    meshes.colliders.push_back(handle);
  }
  return meshes;
}

void update_world(Renderer& renderer, const WorldMeshes& meshes, const World& world) {
  for (size_t k = 0; k < meshes.cloths.size(); ++k) {
    renderer.update_positions(meshes.cloths[k], world.cloths()[k].state.x);
  }
  for (size_t k = 0; k < meshes.colliders.size(); ++k) {
    renderer.set_transform(meshes.colliders[k],
                           collider_placement(world.colliders()[k], meshes.plane_anchor, world.time()));
  }
}

Eigen::AlignedBox3d world_bounds(const World& world) {
  Eigen::AlignedBox3d box;
  for (const Cloth& cloth : world.cloths()) {
    for (int i = 0; i < cloth.num_vertices(); ++i) box.extend(Vec3(cloth.state.x.col(i)));
  }
  for (const Collider& collider : world.colliders()) {
    switch (collider.shape) {
      case ColliderShape::sphere:
        box.extend(Vec3(collider.center - Vec3::Constant(collider.radius)));
        box.extend(Vec3(collider.center + Vec3::Constant(collider.radius)));
        break;
      case ColliderShape::box:
        box.extend(Vec3(collider.center - collider.half_extents));
        box.extend(Vec3(collider.center + collider.half_extents));
        break;
      case ColliderShape::plane:
        break;
      case ColliderShape::capsule:
      case ColliderShape::cylinder:
      case ColliderShape::mesh: {
        const TriangleMesh surface = collider_surface(collider);
        for (int v = 0; v < surface.num_vertices(); ++v) box.extend(Vec3(surface.positions.col(v)));
        break;
      }
    }
  }
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
