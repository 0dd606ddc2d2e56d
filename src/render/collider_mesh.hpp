#pragma once
// Triangle meshes that draw analytic colliders: each in the collider's own frame, plus the rigid
// placement that puts it in the world. No OpenGL here.
#include <Eigen/Geometry>

#include "collision/collider.hpp"
#include "core/triangle_mesh.hpp"

namespace weft {

// Sphere: a UV sphere; box: a box whose faces have their own vertices, so they shade flat; plane:
// a square of half side `plane_half_size` in the local XY plane, front towards +Z; capsule,
// cylinder and mesh: the collision pipeline's surface (collision/collider_geometry.hpp).
TriangleMesh collider_mesh(const Collider& collider, double plane_half_size);

// Places collider_mesh() in the world. A plane's square is centred on the point of the plane
// closest to `plane_anchor` and turned so its front faces the plane's normal; other shapes
// follow their scripted motion at `time`.
Eigen::Isometry3d collider_placement(const Collider& collider, const Vec3& plane_anchor, double time = 0.0);

// The same triangles with three vertices of their own each, so vertex normals are face normals.
TriangleMesh split_vertices(const TriangleMesh& mesh);

}  // namespace weft
