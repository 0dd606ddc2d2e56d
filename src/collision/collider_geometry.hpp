#pragma once
// The triangle mesh that stands for a collider in the collision pipeline, in scene coordinates
// at time 0. Sphere and capsule tessellations are pushed out until every face plane clears the
// analytic solid, so a vertex outside the mesh is outside the shape too; box and plane are exact;
// a cylinder's vertices lie on its surface (its side faces cut inside by at most
// radius (1 - cos(pi / segments))); an OBJ mesh is used as it is.
#include "collision/collider.hpp"
#include "core/triangle_mesh.hpp"

namespace weft {

struct ColliderTessellation {
  int sphere_slices = 48;       // around the axis (sphere, capsule)
  int sphere_stacks = 24;       // pole to pole (sphere); a capsule uses the next odd number
  int cylinder_segments = 96;   // around the axis
};

// Throws std::invalid_argument for a mesh collider without triangles.
TriangleMesh collider_surface(const Collider& collider, const ColliderTessellation& tessellation = {});

}  // namespace weft
